// The final solve of a fit on a large table (a MERL file: a million samples and more), without
// holding its Jacobian.
//
// Ceres' dense solvers store the whole Jacobian, rows x variables (3.3 M x 7 doubles, 184 MB,
// for a MERL table) plus its scratch copies: more than the samples themselves. Every one of our
// problems has at most seven variables, so the normal equations J^T J (7 x 7) and J^T r are all a
// Gauss-Newton step needs, and they are sums over the rows (NormalEquationSums, covariance.h). This
// is Levenberg-Marquardt on those sums, with Ceres' own step control (trust region radius mu, (J^T
// J + diag(J^T J) / mu) delta = -J^T r, the radius grown by 1 / max(1/3, 1 - (2 rho - 1)^3) on
// success and shrunk by a doubling factor on failure; Madsen, Nielsen & Tingleff 2004, §3.2) and
// the same tolerances as ModelFitter::Solve. Steps are clipped to the variables' box, as Ceres
// projects them. The start is the optimum on the stratified subsample, so it usually ends after one
// or two steps. Deterministic: the sums run in a fixed order for any thread count.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/deterministic_reduce.h"
#include "core/text.h"
#include "fitters/covariance.h"
#include "fitters/model_fitter.h"

namespace brdf::fitters {

struct PolishSummary {
  int iterations = 0;
  double initial_cost = 0;  // 1/2 sum r^2, as Ceres reports it
  double final_cost = 0;
  bool converged = false;
  std::string report;  // one line, for the fit report's "termination"
  // The sandwich sums of the last linearization (covariance.h), when it was at the returned
  // variables (every ending but the function tolerance's, which stops at a point it has only
  // evaluated): the covariance there needs no pass of its own.
  bool sums_at_end = false;
  SandwichSums sums;
};

namespace polish_detail {

// The tolerances of ModelFitter::Solve and Ceres' defaults for the step control.
constexpr double kFunctionTolerance = 1e-12;
constexpr double kGradientTolerance = 1e-14;
constexpr double kParameterTolerance = 1e-12;
constexpr double kInitialRadius = 1e4;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kMinDiagonal = 1e-6, kMaxDiagonal = 1e32;

template <typename ModelType>
Eigen::VectorXd Flatten(const ModelFitter<ModelType>& fitter, const Variables& v) {
  Eigen::VectorXd x(fitter.FreeVariables());
  int k = 0;
  for (int c = 0; c < 3; ++c) x[k++] = v.d[c];
  if constexpr (ModelFitter<ModelType>::kLobed) {
    for (int c = 0; c < fitter.SpecularSize(); ++c) x[k++] = v.s[c];
    x[k++] = v.shape[0];
  }
  return x;
}

template <typename ModelType>
Variables Unflatten(const ModelFitter<ModelType>& fitter, const Eigen::VectorXd& x) {
  Variables v;
  int k = 0;
  for (int c = 0; c < 3; ++c) v.d[c] = x[k++];
  if constexpr (ModelFitter<ModelType>::kLobed) {
    for (int c = 0; c < fitter.SpecularSize(); ++c) v.s[c] = x[k++];
    v.shape[0] = x[k++];
  }
  return v;
}

// The normal equations at `v`, their triangles filled in.
template <typename ModelType>
NormalSums Linearize(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                     const Variables& v) {
  NormalSums sums = NormalEquationSums(fitter, problem, v, nullptr);
  sums.a = sums.a.selfadjointView<Eigen::Lower>();
  sums.b = sums.b.selfadjointView<Eigen::Lower>();
  return sums;
}

}  // namespace polish_detail

// Minimizes the problem's cost from `v` (updated in place) within the fitter's variable box.
template <typename ModelType>
PolishSummary StreamedPolish(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                             Variables* v, int max_iterations) {
  using namespace polish_detail;
  const typename ModelFitter<ModelType>::Bounds bounds = fitter.VariableBounds();
  const int n = fitter.FreeVariables();
  const Eigen::Map<const Eigen::VectorXd> lower(bounds.lower.data(), n);
  const Eigen::Map<const Eigen::VectorXd> upper(bounds.upper.data(), n);
  Eigen::VectorXd x = Flatten(fitter, *v);
  NormalSums current = Linearize(fitter, problem, *v);
  bool linearized_at_x = true;
  PolishSummary summary;
  summary.initial_cost = current.cost;
  std::string reason = "maximum iterations reached";
  double radius = kInitialRadius, shrink = 2.0;
  if (!std::isfinite(current.cost)) reason = "the cost at the start is not finite";
  while (std::isfinite(current.cost) && summary.iterations < max_iterations) {
    // Converged when a steepest-descent step projected onto the box no longer moves.
    const Eigen::VectorXd projected = x - (x - current.g).cwiseMax(lower).cwiseMin(upper);
    if (projected.lpNorm<Eigen::Infinity>() <= kGradientTolerance) {
      summary.converged = true;
      reason = "gradient tolerance";
      break;
    }
    const Eigen::VectorXd diagonal =
        current.a.diagonal().cwiseMax(kMinDiagonal).cwiseMin(kMaxDiagonal);
    Eigen::MatrixXd damped = current.a;
    damped.diagonal() += diagonal / radius;
    const Eigen::VectorXd delta = damped.ldlt().solve(-current.g);
    const Eigen::VectorXd candidate = (x + delta).cwiseMax(lower).cwiseMin(upper);
    const Eigen::VectorXd step = candidate - x;
    ++summary.iterations;
    if (!step.allFinite()) {
      reason = "the linear system has no finite solution";
      break;
    }
    if (step.norm() <= kParameterTolerance * (x.norm() + kParameterTolerance)) {
      summary.converged = true;
      reason = "parameter tolerance";
      break;
    }
    const double model_decrease = -(current.g.dot(step) + 0.5 * step.dot(current.a * step));
    const Variables trial = Unflatten(fitter, candidate);
    const double trial_cost = HalfSquaredSum(fitter, problem, trial);
    const double rho = (current.cost - trial_cost) / model_decrease;
    if (std::isfinite(trial_cost) && model_decrease > 0 && rho > kMinRelativeDecrease) {
      const double decrease = current.cost - trial_cost;
      x = candidate;
      *v = trial;
      radius /= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      shrink = 2.0;
      if (decrease <= kFunctionTolerance * current.cost) {
        current.cost = trial_cost;
        linearized_at_x = false;
        summary.converged = true;
        reason = "function tolerance";
        break;
      }
      current = Linearize(fitter, problem, *v);
    } else {
      radius /= shrink;
      shrink *= 2.0;
      if (radius < 1e-32) {  // Ceres' min_trust_region_radius
        summary.converged = true;
        reason = "trust region radius below its minimum";
        break;
      }
    }
  }
  summary.final_cost = current.cost;
  if (linearized_at_x) {
    summary.sums_at_end = true;
    summary.sums = {current.a, current.b};
  }
  summary.report = "streamed Levenberg-Marquardt (normal equations summed over the rows): " +
                   std::to_string(summary.iterations) + " iterations, cost " +
                   FormatNumber(summary.initial_cost, 6) + " -> " +
                   FormatNumber(summary.final_cost, 6) + ", " +
                   (summary.converged ? "CONVERGENCE" : "NO_CONVERGENCE") + " (" + reason + ")";
  return summary;
}

}  // namespace brdf::fitters
