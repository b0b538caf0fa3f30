// Standard errors of a finished fit (DESIGN §6: "stderr", same shape as params).
//
// Sandwich (Huber-White) covariance of the variables, A^-1 B A^-1 with A = sum J_i^T J_i and
// B = sum J_i^T J_i r_i^2, from one pass of the objective's sums (objective.h). It stays right
// when the weights or sigmas do not match the true noise. (ceres::Covariance computes A^-1 by a
// sparse QR of the whole Jacobian: 4.9 s of an 8.9 s fit of a MERL table; the small A from the
// same sums costs one pass — docs/fitting.md.) The model parameters' errors then follow by the
// delta method through the parameterization's Jacobian (Jets).
//
// A logistic variable pushed against its bound (a parameter at 0) or left nothing to share (a
// diffuse term whose albedo budget the lobe used up) has a vanishing derivative and would make A
// singular: such variables are held out, and the parameters that depend on them are reported as
// "not available". A lobe that vanishes at a zero
// share (models/term.h: kVanishesAtZero) with its share at the lower bound in every channel has
// no shape to measure; its shape is held out too.
#pragma once

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fitters/objective.h"
#include "fitters/parameterization.h"

namespace brdf::fitters {

// |logistic variable| beyond which its derivative (< 1e-10) no longer informs the covariance.
inline constexpr double kSaturated = 23.0;
// Smallest eigenvalue of J^T J, relative to the largest, for the variables to count as
// identifiable.
inline constexpr double kRankTolerance = 1e-13;

// The variables held out of the covariance at `x`: logistic variables pushed against their
// bound, and a vanished lobe's shape (with `note` saying so).
template <typename M>
std::vector<bool> HeldVariables(bool grey_specular, const std::vector<double>& x,
                                std::string* note) {
  const std::vector<bool> shapes = VariableLayout<M>::Shapes(grey_specular);
  const auto offsets = VariableLayout<M>::Offsets(grey_specular);
  std::vector<bool> held(x.size(), false);
  for (size_t k = 0; k < x.size(); ++k) held[k] = !shapes[k] && std::abs(x[k]) >= kSaturated;
  M::ForEachLobe([&](auto lobe, auto index) {
    using Lobe = decltype(lobe);
    if (!Lobe::kVanishesAtZero) return;
    const int first = offsets[index];
    const int count = Lobe::NumVariables(VariableLayout<M>::Grey(index, grey_specular));
    bool vanished = true;
    for (int k = first; k < first + count - 1; ++k) vanished = vanished && x[k] <= -kSaturated;
    if (vanished) {
      held[first + count - 1] = true;
      *note = std::string("the lobe vanished (") + Lobe::Params().front().name + " at 0): its " +
              (Lobe::kShapeScale == models::ShapeScale::kExponent ? "exponent" : "width") +
              " is not identifiable";
    }
  });
  return held;
}

// The sandwich A^-1 B A^-1 on the variables not `held` (held ones get NaN on the diagonal).
// False, with `note`, when A is rank-deficient there.
inline bool SandwichCovariance(const Eigen::MatrixXd& full_a, const Eigen::MatrixXd& full_b,
                               const std::vector<bool>& held, Eigen::MatrixXd* covariance,
                               std::string* note) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const int n = static_cast<int>(held.size());
  std::vector<int> free;
  for (int k = 0; k < n; ++k) {
    if (!held[k]) free.push_back(k);
  }
  const int m = static_cast<int>(free.size());
  Eigen::MatrixXd a(m, m), b(m, m);
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

// Covariance of the variables at `x` from the normal sums there (A and B, lower triangles or
// full); held variables carry NaN on the diagonal. False, with `note`, when A is rank-deficient.
template <typename M>
bool VariableCovariance(bool grey_specular, const std::vector<double>& x, const NormalSums& sums,
                        Eigen::MatrixXd* covariance, std::string* note) {
  std::vector<bool> held = HeldVariables<M>(grey_specular, x, note);
  const Eigen::MatrixXd a = sums.a.template selfadjointView<Eigen::Lower>();
  const Eigen::MatrixXd b = sums.b.template selfadjointView<Eigen::Lower>();
  // A share whose column of A the rank test cannot see has nothing to share out: its budget is
  // used up (the diffuse term after a lobe that took the whole albedo), so the data cannot move
  // it. A shape with no information stays in, and the test reports it.
  const std::vector<bool> shapes = VariableLayout<M>::Shapes(grey_specular);
  const double largest = a.diagonal().maxCoeff();
  for (size_t k = 0; k < held.size(); ++k) {
    held[k] = held[k] || (!shapes[k] && !(a(k, k) > kRankTolerance * largest));
  }
  return SandwichCovariance(a, b, held, covariance, note);
}

// d params / d variables at a point (one row per model parameter).
template <typename M>
Eigen::MatrixXd ParamGradients(const typename FitObjective<M>::Point& at, int n) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      at.gradients.data(), M::kNumParams, n);
}

// Standard errors of the model parameters by the delta method through the parameterization's
// Jacobian at `at` (automatic differentiation with Jets).
template <typename M>
std::vector<double> ParamStderr(const typename FitObjective<M>::Point& at,
                                const Eigen::MatrixXd& covariance) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const int n = static_cast<int>(covariance.rows());
  const Eigen::MatrixXd gradients = ParamGradients<M>(at, n);
  // Held (at-the-bound) variables carry NaN on the diagonal and zeros elsewhere; a parameter
  // that depends on one, or on no variable at all, gets NaN, "not available".
  Eigen::MatrixXd finite_covariance = covariance;
  std::vector<bool> held(n);
  for (int k = 0; k < n; ++k) {
    held[k] = std::isnan(covariance(k, k));
    if (held[k]) finite_covariance(k, k) = 0.0;
  }
  std::vector<double> errors(M::kNumParams);
  for (int p = 0; p < M::kNumParams; ++p) {
    const Eigen::VectorXd gradient = gradients.row(p).transpose();
    // A parameter no variable moves (a share of a used-up budget) is pinned, not measured.
    bool depends_on_held = gradient.isZero(0.0);
    for (int k = 0; k < n; ++k) depends_on_held = depends_on_held || (held[k] && gradient[k] != 0);
    errors[p] = depends_on_held
                    ? kNaN
                    : std::sqrt(std::max(0.0, gradient.dot(finite_covariance * gradient)));
  }
  return errors;
}

}  // namespace brdf::fitters
