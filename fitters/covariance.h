// Standard errors of a finished fit (DESIGN §6: "stderr", same shape as params).
//
// Sandwich (Huber-White) covariance of the variables, A^-1 B A^-1 with A = sum J_i^T J_i and
// B = sum J_i^T J_i r_i^2, accumulated in one parallel pass over the residual blocks. It stays
// right when the weights or sigmas do not match the true noise. (ceres::Covariance computes
// A^-1 by a sparse QR of the whole Jacobian: 4.9 s of an 8.9 s fit of a MERL table; the 7x7 A
// from the same Jacobians costs one pass — docs/fitting.md.) The model parameters' errors then
// follow by the delta method through the parameterization's Jacobian (Jets).
//
// A logistic variable pushed against its bound (a parameter at 0, an albedo budget used up) has
// a vanishing derivative and would make A singular: such variables are held out, and the
// parameters that depend on them are reported as "not available". A power-cosine lobe share at
// its lower bound in every channel means the lobe vanished; its exponent shapes nothing and is
// held out too.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/deterministic_reduce.h"
#include "fitters/model_fitter.h"

namespace brdf::fitters {

// |logistic variable| beyond which its derivative (< 1e-10) no longer informs the covariance.
inline constexpr double kSaturated = 23.0;
// Smallest eigenvalue of J^T J, relative to the largest, for the variables to count as
// identifiable.
inline constexpr double kRankTolerance = 1e-13;

// Covariance of the fitter's variables (d, s, shape) at `v`; held variables carry NaN on the
// diagonal. False, with `note`, when A is rank-deficient.
template <typename ModelType>
bool VariableCovariance(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                        const Variables& v, Eigen::MatrixXd* covariance, std::string* note) {
  constexpr bool kLobed = ModelFitter<ModelType>::kLobed;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<double*> blocks;
  std::vector<int> sizes;
  const int s_size = fitter.SpecularSize();
  Variables at = v;
  blocks.push_back(at.d);
  sizes.push_back(3);
  if (kLobed) {
    blocks.insert(blocks.end(), {at.s, at.shape});
    sizes.insert(sizes.end(), {s_size, 1});
  }
  const int n = fitter.FreeVariables();
  std::vector<bool> held(n, false);
  // Only a power-cosine lobe can vanish: a microfacet lobe with f0 = 0 still has Schlick's rise.
  bool lobe_vanished = kLobed && ModelType::kFamily == models::ModelFamily::kPowerCosine;
  for (int k = 0; k < 3; ++k) held[k] = std::abs(v.d[k]) >= kSaturated;
  for (int k = 0; k < s_size; ++k) {
    held[3 + k] = std::abs(v.s[k]) >= kSaturated;
    lobe_vanished = lobe_vanished && v.s[k] <= -kSaturated;
  }
  if (lobe_vanished) {
    held[n - 1] = true;
    *note = "the lobe vanished (rho_s at 0): its exponent is not identifiable";
  }

  std::vector<ceres::ResidualBlockId> residual_blocks;
  problem->GetResidualBlocks(&residual_blocks);
  struct Sums {
    Eigen::MatrixXd a, b;
  };
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(n, n);
  // One residual block per chunk (each evaluates in parallel), summed in a fixed order.
  const Sums sums = DeterministicReduce(
      static_cast<int64_t>(residual_blocks.size()), 1, Sums{zero, zero},
      [&](int64_t begin, int64_t end, Sums partial) {
        std::vector<double> residuals;
        std::vector<std::vector<double>> jacobians(blocks.size());
        std::vector<double*> jacobian_pointers(blocks.size());
        Eigen::VectorXd row(n);
        for (int64_t index = begin; index < end; ++index) {
          const ceres::CostFunction* cost =
              problem->GetCostFunctionForResidualBlock(residual_blocks[index]);
          const int rows = cost->num_residuals();
          residuals.resize(rows);
          for (size_t b = 0; b < blocks.size(); ++b) {
            jacobians[b].resize(rows * sizes[b]);
            jacobian_pointers[b] = jacobians[b].data();
          }
          cost->Evaluate(blocks.data(), residuals.data(), jacobian_pointers.data());
          for (int r = 0; r < rows; ++r) {
            int column = 0;
            for (size_t b = 0; b < blocks.size(); ++b) {
              for (int k = 0; k < sizes[b]; ++k) row[column++] = jacobians[b][r * sizes[b] + k];
            }
            partial.a.template selfadjointView<Eigen::Lower>().rankUpdate(row);
            partial.b.template selfadjointView<Eigen::Lower>().rankUpdate(
                row, residuals[r] * residuals[r]);
          }
        }
        return partial;
      },
      [](Sums x, const Sums& y) {
        x.a += y.a;
        x.b += y.b;
        return x;
      });

  // Invert A on the free (not held) variables.
  std::vector<int> free;
  for (int k = 0; k < n; ++k) {
    if (!held[k]) free.push_back(k);
  }
  const int m = static_cast<int>(free.size());
  Eigen::MatrixXd a(m, m), b(m, m);
  const Eigen::MatrixXd full_a = sums.a.template selfadjointView<Eigen::Lower>();
  const Eigen::MatrixXd full_b = sums.b.template selfadjointView<Eigen::Lower>();
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      a(i, j) = full_a(free[i], free[j]);
      b(i, j) = full_b(free[i], free[j]);
    }
  }
  *covariance = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) {
    if (held[k]) (*covariance)(k, k) = kNaN;  // marks "held" for ParamStderr
  }
  if (m == 0) return true;  // every variable is at a bound
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(a);
  const Eigen::VectorXd values = eigen.eigenvalues();
  if (!(values.minCoeff() > kRankTolerance * values.maxCoeff())) {
    *note =
        "rank-deficient: not every parameter is identifiable from these data (for example a "
        "lobe fitted to matte data leaves its width free)";
    return false;
  }
  const Eigen::MatrixXd a_inverse =
      eigen.eigenvectors() * values.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose();
  const Eigen::MatrixXd free_covariance = a_inverse * b * a_inverse;
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) (*covariance)(free[i], free[j]) = free_covariance(i, j);
  }
  return true;
}

// Standard errors of the model parameters by the delta method through the parameterization's
// Jacobian (automatic differentiation with Jets).
template <typename ModelType>
std::vector<double> ParamStderr(const ModelFitter<ModelType>& fitter, const Variables& v,
                                const Eigen::MatrixXd& covariance) {
  using Jet = ceres::Jet<double, FitVariables::kMaxVariables>;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const int n = static_cast<int>(covariance.rows());
  Jet d[3], s[3], shape[1];
  int slot = 0;
  for (int c = 0; c < 3; ++c) d[c] = Jet(v.d[c], slot++);
  for (int c = 0; c < fitter.SpecularSize(); ++c) s[c] = Jet(v.s[c], slot++);
  if (ModelFitter<ModelType>::kLobed) shape[0] = Jet(v.shape[0], slot++);
  Jet params[ModelType::kNumParams];
  VariablesToParams<ModelType, Jet>(fitter.options().grey_specular, d, s, shape, params);
  // Held (at-the-bound) variables carry NaN on the diagonal and zeros elsewhere; a parameter
  // that depends on one gets NaN, "not available".
  Eigen::MatrixXd finite_covariance = covariance;
  std::vector<bool> held(n);
  for (int k = 0; k < n; ++k) {
    held[k] = std::isnan(covariance(k, k));
    if (held[k]) finite_covariance(k, k) = 0.0;
  }
  std::vector<double> errors(ModelType::kNumParams);
  for (int p = 0; p < ModelType::kNumParams; ++p) {
    const Eigen::VectorXd gradient = params[p].v.head(n);
    bool depends_on_held = false;
    for (int k = 0; k < n; ++k) depends_on_held = depends_on_held || (held[k] && gradient[k] != 0);
    errors[p] = depends_on_held
                    ? kNaN
                    : std::sqrt(std::max(0.0, gradient.dot(finite_covariance * gradient)));
  }
  return errors;
}

}  // namespace brdf::fitters
