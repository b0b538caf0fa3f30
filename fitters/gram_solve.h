// Ceres' Levenberg-Marquardt on a fit's least squares, through a stand-in of n + 1 residuals.
//
// Every step of Levenberg-Marquardt needs only the cost 1/2 |r|^2, the gradient J^T r and the
// Gauss-Newton matrix J^T J of the rows at the current variables, and the cost alone at a trial
// point. Those three are the blocks of the augmented Gram matrix
//   M = [J r]^T [J r]   ((n + 1) x (n + 1), n <= 7 variables),
// which NormalEquationSums (covariance.h) adds up batch by batch without forming J. Any
// W = [J' r'] with W^T W = M has the same cost, gradient and Gauss-Newton matrix, so Ceres, handed
// the n + 1 residuals r' with Jacobian J', takes the steps it would take on the rows: the same
// trust region, the same Jacobi scaling (the column norms of J' are those of J), the same
// tolerances. What it no longer does is copy, check and multiply out a Jacobian of
// 3 x samples rows at every evaluation, which cost more than the model itself.
//
// W comes from the eigen decomposition of M scaled to a unit diagonal, D^-1 M D^-1 = U S U^T,
// W = S^1/2 U^T D: each entry of W^T W is then exact to rounding relative to its own diagonal,
// so a cost many orders below the curvature (a noise-free fit near its optimum) keeps its
// digits. A trial point's cost is the rows' own (HalfSquaredSum), as the last residual.
//
// Ceres asks for the Jacobian at a point it has asked for just before (22-42 % of the requests of
// `--model auto` on a MERL-sized table), so the last W is kept with its variables
// (LastCallOfVariables, parameterization.h) and handed out again: the pass over the rows is what
// costs.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <memory>
#include <vector>

#include "fitters/covariance.h"
#include "fitters/model_fitter.h"

namespace brdf::fitters {

template <typename ModelType>
class GramCost final : public ceres::CostFunction {
 public:
  // The least squares over `samples` (which must outlive this function).
  GramCost(const ModelFitter<ModelType>& fitter, const std::vector<FitSample>& samples)
      : fitter_(fitter), rows_(fitter.BuildProblem(samples, &unused_)) {
    const int n = fitter.FreeVariables();
    if constexpr (ModelFitter<ModelType>::kLobed) {
      *mutable_parameter_block_sizes() = {3, fitter.SpecularSize(), 1};
    } else {
      *mutable_parameter_block_sizes() = {3};
    }
    set_num_residuals(n + 1);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int n = fitter_.FreeVariables();
    Variables at;
    for (int c = 0; c < 3; ++c) at.d[c] = parameters[0][c];
    if constexpr (ModelFitter<ModelType>::kLobed) {
      for (int c = 0; c < fitter_.SpecularSize(); ++c) at.s[c] = parameters[1][c];
      at.shape[0] = parameters[2][0];
    }
    if (jacobians == nullptr) {
      const double cost = HalfSquaredSum(fitter_, rows_.get(), at);
      for (int i = 0; i < n; ++i) residuals[i] = 0;
      residuals[n] = std::sqrt(2 * cost);
      return std::isfinite(cost);
    }
    LastW key;
    key.SetKey<ModelType>(fitter_.options().grey_specular, at.d, at.s, at.shape);
    const int entries = (n + 1) * (n + 1);
    Eigen::MatrixXd w(n + 1, n + 1);
    if (!last_.Find(key, w.data(), entries)) {
      if (!Factor(at, &w)) return false;
      last_.Keep(key, w.data(), entries);
    }
    for (int i = 0; i <= n; ++i) residuals[i] = w(i, n);
    const std::vector<int32_t>& sizes = parameter_block_sizes();
    int column = 0;
    for (size_t block = 0; block < sizes.size(); ++block) {
      if (jacobians[block] != nullptr) {
        for (int i = 0; i <= n; ++i) {
          for (int j = 0; j < sizes[block]; ++j) {
            jacobians[block][i * sizes[block] + j] = w(i, column + j);
          }
        }
      }
      column += sizes[block];
    }
    return true;
  }

 private:
  // W at `at` (the header); false if the sums are not finite or not decomposed.
  bool Factor(const Variables& at, Eigen::MatrixXd* w_out) const {
    const int n = fitter_.FreeVariables();
    const NormalSums sums = NormalEquationSums(fitter_, rows_.get(), at, nullptr);
    Eigen::MatrixXd gram(n + 1, n + 1);
    gram.topLeftCorner(n, n) = sums.a.template selfadjointView<Eigen::Lower>();
    gram.col(n).head(n) = sums.g;
    gram.row(n).head(n) = sums.g.transpose();
    gram(n, n) = 2 * sums.cost;
    if (!gram.allFinite()) return false;
    Eigen::VectorXd scale(n + 1);
    for (int i = 0; i <= n; ++i) scale[i] = gram(i, i) > 0 ? std::sqrt(gram(i, i)) : 1.0;
    const Eigen::MatrixXd unit =
        scale.cwiseInverse().asDiagonal() * gram * scale.cwiseInverse().asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(unit);
    if (eigen.info() != Eigen::Success) return false;
    *w_out = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
             eigen.eigenvectors().transpose() * scale.asDiagonal();
    return true;
  }

  const ModelFitter<ModelType>& fitter_;
  Variables unused_;  // the rows' problem is only read through its cost functions
  std::unique_ptr<ceres::Problem> rows_;
  // The last Jacobian evaluation's W, column by column. One problem is evaluated on one thread
  // (its one residual block), so no lock guards it.
  using LastW =
      LastCallOfVariables<(FitVariables::kMaxVariables + 1) * (FitVariables::kMaxVariables + 1)>;
  mutable LastW last_;
};

// Minimizes the least squares over `samples` from `v` (updated in place) within the fitter's box,
// as ModelFitter::Solve would on BuildProblem(samples, v), through GramCost.
template <typename ModelType>
ceres::Solver::Summary SolveLeastSquares(const ModelFitter<ModelType>& fitter,
                                         const std::vector<FitSample>& samples, Variables* v,
                                         int max_iterations) {
  ceres::Problem problem;
  auto* cost = new GramCost<ModelType>(fitter, samples);
  if constexpr (ModelFitter<ModelType>::kLobed) {
    problem.AddResidualBlock(cost, nullptr, v->d, v->s, v->shape);
  } else {
    problem.AddResidualBlock(cost, nullptr, v->d);
  }
  fitter.SetVariableBounds(&problem, v);
  return fitter.Solve(&problem, max_iterations);
}

}  // namespace brdf::fitters
