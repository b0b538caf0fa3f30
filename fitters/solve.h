// Every solve of a fit: Ceres' Levenberg-Marquardt on a FitObjective (objective.h), through a
// stand-in of n + 1 residuals.
//
// Every step of Levenberg-Marquardt needs only the cost 1/2 |r|^2, the gradient J^T r and the
// Gauss-Newton matrix J^T J of the rows at the current variables, and the cost at a trial point.
// Those three are the blocks of the augmented Gram matrix
//   M = [J r]^T [J r]   ((n + 1) x (n + 1), n the variables),
// which the objective adds up batch by batch without forming J. Any W = [J' r'] with W^T W = M
// has the same cost, gradient and Gauss-Newton matrix, so Ceres, handed the n + 1 residuals r'
// with Jacobian J', takes the steps it would take on the rows: the same trust region, the same
// Jacobi scaling (the column norms of J' are those of J), the same tolerances. It never copies,
// checks or multiplies out a Jacobian of 3 x samples rows (for a MERL table, 3.3 M x 7 doubles),
// so one solver path serves a 20-sample file and a million-sample table alike.
//
// W comes from the eigen decomposition of M scaled to a unit diagonal, D^-1 M D^-1 = U S U^T,
// W = S^1/2 U^T D: each entry of W^T W is then exact to rounding relative to its own diagonal,
// so a cost many orders below the curvature (a noise-free fit near its optimum) keeps its
// digits. A trial point's cost is the sums' own, as the last residual.
//
// Ceres asks for the cost alone at a trial point and, once it has accepted the step, for the
// Jacobian at the same point (sometimes twice); its EvaluationCallback says when the point is
// new. PointEvaluation makes the sums at every new point, trial or not, in one pass over the
// rows: the model's value comes with its gradient at little more than its own cost, and nearly
// every step is accepted, so a cost-only pass at the trial point followed by the full pass cost
// more (an `auto` fit of a bundled Cornell file 9 % more, a MERL table's blinn-phong fit 4 %;
// docs/performance.md).
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "fitters/objective.h"

namespace brdf::fitters {

// The tolerances of every solve.
struct SolveTolerances {
  static constexpr double kFunction = 1e-12;
  static constexpr double kGradient = 1e-14;
  static constexpr double kParameter = 1e-12;
};

// W at a point from its normal sums (the header); false if they are not finite or not decomposed.
inline bool GramFactor(const NormalSums& sums, Eigen::MatrixXd* w) {
  const int n = static_cast<int>(sums.g.size());
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
  *w = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
       eigen.eigenvectors().transpose() * scale.asDiagonal();
  return true;
}

// The objective at the point Ceres is about to evaluate (the variables' own memory, which Ceres
// fills before it calls PrepareForEvaluation): its sums, cost and W, made once per point.
template <typename M>
class PointEvaluation final : public ceres::EvaluationCallback {
 public:
  PointEvaluation(const FitObjective<M>& objective, const double* x)
      : objective_(objective), x_(x) {}

  void PrepareForEvaluation(bool, bool new_evaluation_point) override {
    if (have_w_ && !new_evaluation_point) return;
    sums_ = objective_.Sums(objective_.At(x_));
    sums_point_.assign(x_, x_ + objective_.NumVariables());
    ok_ = GramFactor(sums_, &w_);
    have_w_ = true;
  }

  bool ok() const { return ok_; }
  double cost() const { return sums_.cost; }
  bool has_w() const { return have_w_; }
  const Eigen::MatrixXd& w() const { return w_; }
  // The normal sums of the last point evaluated, and that point.
  const NormalSums& sums() const { return sums_; }
  const std::vector<double>& sums_point() const { return sums_point_; }

 private:
  const FitObjective<M>& objective_;
  const double* x_;
  bool have_w_ = false, ok_ = false;
  Eigen::MatrixXd w_;
  NormalSums sums_;
  std::vector<double> sums_point_;
};

// The n + 1 stand-in residuals of the header, read from the point's evaluation.
template <typename M>
class GramCost final : public ceres::CostFunction {
 public:
  GramCost(const PointEvaluation<M>& evaluation, int n) : evaluation_(evaluation), n_(n) {
    *mutable_parameter_block_sizes() = {n};
    set_num_residuals(n + 1);
  }

  bool Evaluate(double const* const*, double* residuals, double** jacobians) const override {
    if (!evaluation_.ok()) return false;
    if (jacobians == nullptr) {
      for (int i = 0; i < n_; ++i) residuals[i] = 0;
      residuals[n_] = std::sqrt(2 * evaluation_.cost());
      return true;
    }
    const Eigen::MatrixXd& w = evaluation_.w();
    for (int i = 0; i <= n_; ++i) residuals[i] = w(i, n_);
    if (jacobians[0] != nullptr) {
      for (int i = 0; i <= n_; ++i) {
        for (int j = 0; j < n_; ++j) jacobians[0][i * n_ + j] = w(i, j);
      }
    }
    return true;
  }

 private:
  const PointEvaluation<M>& evaluation_;
  int n_;
};

// Minimizes the objective from `x` (updated in place) within the box [lower, upper]. When
// `sums_at_end` is given and the solve's last evaluation was at the final `x` (unless Ceres
// rejected its last trial point), it receives the normal sums there and `*have_sums` is set: the
// standard errors at the optimum then need no pass of their own.
template <typename M>
ceres::Solver::Summary SolveLeastSquares(const FitObjective<M>& objective, std::vector<double>* x,
                                         const std::vector<double>& lower,
                                         const std::vector<double>& upper, int max_iterations,
                                         NormalSums* sums_at_end = nullptr,
                                         bool* have_sums = nullptr) {
  const int n = objective.NumVariables();
  PointEvaluation<M> evaluation(objective, x->data());
  ceres::Problem::Options problem_options;
  problem_options.evaluation_callback = &evaluation;
  ceres::Problem problem(problem_options);
  problem.AddResidualBlock(new GramCost<M>(evaluation, n), nullptr, x->data());
  for (int k = 0; k < n; ++k) {
    problem.SetParameterLowerBound(x->data(), k, lower[k]);
    problem.SetParameterUpperBound(x->data(), k, upper[k]);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.max_num_iterations = max_iterations;
  // One solver thread: the objective evaluates its batches in parallel, so the result does not
  // depend on the thread count.
  options.num_threads = 1;
  options.function_tolerance = SolveTolerances::kFunction;
  options.gradient_tolerance = SolveTolerances::kGradient;
  options.parameter_tolerance = SolveTolerances::kParameter;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (sums_at_end != nullptr) {
    *have_sums = evaluation.has_w() && evaluation.sums_point() == *x;
    if (*have_sums) *sums_at_end = evaluation.sums();
  }
  return summary;
}

}  // namespace brdf::fitters
