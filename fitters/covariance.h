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
#include "fitters/analytic_cost.h"
#include "fitters/model_fitter.h"
#include "fitters/parallel_cost.h"

namespace brdf::fitters {

// |logistic variable| beyond which its derivative (< 1e-10) no longer informs the covariance.
inline constexpr double kSaturated = 23.0;
// Smallest eigenvalue of J^T J, relative to the largest, for the variables to count as
// identifiable.
inline constexpr double kRankTolerance = 1e-13;

// The fitter's variables held out of the covariance at `v`: logistic variables pushed against
// their bound, and a vanished power-cosine lobe's exponent (with `note` saying so).
template <typename ModelType>
std::vector<bool> HeldVariables(const ModelFitter<ModelType>& fitter, const Variables& v,
                                std::string* note) {
  constexpr bool kLobed = ModelFitter<ModelType>::kLobed;
  const int n = fitter.FreeVariables();
  const int s_size = fitter.SpecularSize();
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
  return held;
}

// The parameter blocks of the fitter's problem at `v` (copied into `at`) and their sizes.
template <typename ModelType>
void ProblemBlocks(const ModelFitter<ModelType>& fitter, Variables* at,
                   std::vector<double*>* blocks, std::vector<int>* sizes) {
  blocks->assign({at->d});
  sizes->assign({3});
  if (ModelFitter<ModelType>::kLobed) {
    blocks->insert(blocks->end(), {at->s, at->shape});
    sizes->insert(sizes->end(), {fitter.SpecularSize(), 1});
  }
}

// A residual block's Jacobian: one row per residual, the parameter blocks side by side.
using BlockJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Evaluates one cost function (a residual block, or one batch of it) at `blocks`: its residuals
// and, unless `jacobian` is null, its Jacobian (rows x n). A function that fails to evaluate
// reads as infinite residuals. `scratch` holds the parameter blocks' Jacobians between calls.
inline void EvaluateBlock(const ceres::CostFunction* cost, const std::vector<double*>& blocks,
                          const std::vector<int>& sizes, int n, Eigen::VectorXd* residuals,
                          BlockJacobian* jacobian, std::vector<std::vector<double>>* scratch) {
  const int rows = cost->num_residuals();
  residuals->resize(rows);
  scratch->resize(jacobian != nullptr ? blocks.size() : 0);
  std::vector<double*> jacobian_pointers(scratch->size());
  for (size_t b = 0; b < scratch->size(); ++b) {
    (*scratch)[b].resize(static_cast<size_t>(rows) * sizes[b]);
    jacobian_pointers[b] = (*scratch)[b].data();
  }
  if (!cost->Evaluate(blocks.data(), residuals->data(),
                      jacobian != nullptr ? jacobian_pointers.data() : nullptr)) {
    residuals->setConstant(std::numeric_limits<double>::infinity());
  }
  if (jacobian == nullptr) return;
  jacobian->resize(rows, n);
  int column = 0;
  for (size_t b = 0; b < blocks.size(); ++b) {
    jacobian->middleCols(column, sizes[b]) =
        Eigen::Map<const BlockJacobian>((*scratch)[b].data(), rows, sizes[b]);
    column += sizes[b];
  }
}

// Evaluates one residual block and calls visit(r, jacobian_row, residual) for its rows.
template <typename Visit>
void VisitBlockRows(const ceres::CostFunction* cost, const std::vector<double*>& blocks,
                    const std::vector<int>& sizes, int n, Visit&& visit) {
  Eigen::VectorXd residuals;
  BlockJacobian jacobian;
  std::vector<std::vector<double>> scratch;
  EvaluateBlock(cost, blocks, sizes, n, &residuals, &jacobian, &scratch);
  for (int r = 0; r < jacobian.rows(); ++r) {
    const Eigen::VectorXd row = jacobian.row(r).transpose();
    visit(r, row, residuals[r]);
  }
}

// Calls visit(row_index, jacobian_row, residual) for every residual row of `problem` at `v`
// (rows numbered in the problem's order: sample k's channel c is row 3 k + c), from the same
// cost functions Ceres differentiates; blocks in order, each evaluating its batches in parallel.
template <typename ModelType, typename Visit>
void ForEachJacobianRow(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                        const Variables& v, Visit&& visit) {
  Variables at = v;
  std::vector<double*> blocks;
  std::vector<int> sizes;
  ProblemBlocks(fitter, &at, &blocks, &sizes);
  std::vector<ceres::ResidualBlockId> residual_blocks;
  problem->GetResidualBlocks(&residual_blocks);
  int64_t first_row = 0;
  for (const ceres::ResidualBlockId id : residual_blocks) {
    const ceres::CostFunction* cost = problem->GetCostFunctionForResidualBlock(id);
    VisitBlockRows(cost, blocks, sizes, fitter.FreeVariables(),
                   [&](int r, const Eigen::VectorXd& row, double residual) {
                     visit(first_row + r, row, residual);
                   });
    first_row += cost->num_residuals();
  }
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

// Cost functions per chunk of ReduceOverBatches: 16 batches of 256 samples, a chunk's Jacobians
// stay in the core's cache.
inline constexpr int64_t kBatchesPerChunk = 16;

// Reduces over the batches of every residual block of `problem` (ParallelBatchCost; a block of
// another kind as a whole): visit(partial, cost, first_row, blocks, sizes) for each, with
// `blocks` the parameter blocks at `v` and rows numbered in the problem's order (sample k's
// channel c is row 3 k + c). One parallel pass, the partial results combined in a fixed order,
// so the result does not depend on the thread count. A batch's Jacobian is a few tens of kB and
// stays in cache; a whole block's would be tens of MB, allocated and touched anew.
template <typename ModelType, typename Value, typename Visit, typename Combine>
Value ReduceOverBatches(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                        const Variables& v, const Value& zero, Visit&& visit, Combine&& combine) {
  Variables at = v;
  std::vector<double*> blocks;
  std::vector<int> sizes;
  ProblemBlocks(fitter, &at, &blocks, &sizes);
  struct Batch {
    const ceres::CostFunction* cost;
    int64_t first_row;
  };
  std::vector<Batch> batches;
  std::vector<ceres::ResidualBlockId> residual_blocks;
  problem->GetResidualBlocks(&residual_blocks);
  int64_t block_row = 0;
  for (const ceres::ResidualBlockId id : residual_blocks) {
    const ceres::CostFunction* cost = problem->GetCostFunctionForResidualBlock(id);
    if (const auto* batched = dynamic_cast<const ParallelBatchCost*>(cost)) {
      for (size_t b = 0; b < batched->batch_count(); ++b) {
        batches.push_back({&batched->batch(b), block_row + batched->first_row(b)});
      }
    } else {
      batches.push_back({cost, block_row});
    }
    block_row += cost->num_residuals();
  }
  return DeterministicReduce(
      static_cast<int64_t>(batches.size()), kBatchesPerChunk, zero,
      [&](int64_t begin, int64_t end, Value partial) {
        for (int64_t index = begin; index < end; ++index) {
          visit(partial, *batches[index].cost, batches[index].first_row, blocks, sizes);
        }
        return partial;
      },
      combine);
}

// 1/2 sum r^2 over the problem at `v`, residuals only (no derivatives), summed batch by batch
// in the fixed order of ReduceOverBatches.
template <typename ModelType>
double HalfSquaredSum(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                      const Variables& v) {
  const int n = fitter.FreeVariables();
  return ReduceOverBatches(
      fitter, problem, v, 0.0,
      [&](double& partial, const ceres::CostFunction& cost, int64_t,
          const std::vector<double*>& blocks, const std::vector<int>& sizes) {
        Eigen::VectorXd residuals;
        std::vector<std::vector<double>> scratch;
        EvaluateBlock(&cost, blocks, sizes, n, &residuals, nullptr, &scratch);
        partial += 0.5 * residuals.squaredNorm();
      },
      [](double a, double b) { return a + b; });
}

// A = sum J_i^T J_i and B = sum J_i^T J_i e_i over residual rows i: the sandwich's two sums.
struct SandwichSums {
  Eigen::MatrixXd a, b;
};

// Adds a block's rows to the lower triangles of A = sum J_i^T J_i and B = sum J_i^T J_i e_i
// (one e_i >= 0 per row: a squared residual or the expectation of one).
inline void AddSandwichSums(const BlockJacobian& jacobian, const Eigen::VectorXd& e,
                            Eigen::MatrixXd* a, Eigen::MatrixXd* b) {
  const BlockJacobian weighted = e.cwiseSqrt().asDiagonal() * jacobian;  // sqrt(e) J
  a->selfadjointView<Eigen::Lower>().rankUpdate(jacobian.transpose());
  b->selfadjointView<Eigen::Lower>().rankUpdate(weighted.transpose());
}

// The sums of the normal equations over the residual rows i of `problem` at `v`:
// A = sum J_i^T J_i, B = sum J_i^T J_i e_i, g = J^T r and cost = 1/2 |r|^2, with e_i the squared
// residual itself or, when `expected_squared` is given, its expectation (one per row, in the
// problem's order). A and B are lower triangles. An analytic batch (analytic_cost.h) adds its
// terms without forming its Jacobian; any other batch through its Jacobian rows.
struct NormalSums {
  Eigen::MatrixXd a, b;
  Eigen::VectorXd g;
  double cost = 0;
};
template <typename ModelType>
NormalSums NormalEquationSums(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                              const Variables& v, const std::vector<double>* expected_squared) {
  const int n = fitter.FreeVariables();
  const NormalSums zero{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n),
                        Eigen::VectorXd::Zero(n), 0.0};
  return ReduceOverBatches(
      fitter, problem, v, zero,
      [&](NormalSums& partial, const ceres::CostFunction& cost, int64_t first_row,
          const std::vector<double*>& blocks, const std::vector<int>& sizes) {
        const double* expected =
            expected_squared != nullptr ? expected_squared->data() + first_row : nullptr;
        if constexpr (kHasLobe<ModelType>) {
          if (const auto* analytic = dynamic_cast<const AnalyticBatchCost<ModelType>*>(&cost)) {
            analytic->AddNormalSums(blocks.data(), expected, &partial.a, &partial.b, &partial.g,
                                    &partial.cost);
            return;
          }
        }
        Eigen::VectorXd residuals;
        BlockJacobian jacobian;
        std::vector<std::vector<double>> scratch;
        EvaluateBlock(&cost, blocks, sizes, n, &residuals, &jacobian, &scratch);
        const Eigen::VectorXd e =
            expected != nullptr
                ? Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(expected, residuals.size()))
                : Eigen::VectorXd(residuals.array().square());
        AddSandwichSums(jacobian, e, &partial.a, &partial.b);
        partial.g.noalias() += jacobian.transpose() * residuals;
        partial.cost += 0.5 * residuals.squaredNorm();
      },
      [](NormalSums x, const NormalSums& y) {
        x.a += y.a;
        x.b += y.b;
        x.g += y.g;
        x.cost += y.cost;
        return x;
      });
}

// A = sum J_i^T J_i and B = sum J_i^T J_i e_i over the residual rows i (NormalEquationSums): then
// A^-1 B A^-1 is the covariance a fit of these samples will have, before any data exist, when
// `expected_squared` is given (experiment_design.h).
template <typename ModelType>
void JacobianSums(const ModelFitter<ModelType>& fitter, ceres::Problem* problem, const Variables& v,
                  const std::vector<double>* expected_squared, Eigen::MatrixXd* a,
                  Eigen::MatrixXd* b) {
  const NormalSums sums = NormalEquationSums(fitter, problem, v, expected_squared);
  *a = sums.a.template selfadjointView<Eigen::Lower>();
  *b = sums.b.template selfadjointView<Eigen::Lower>();
}

// Covariance of the fitter's variables (d, s, shape) at `v`; held variables carry NaN on the
// diagonal. False, with `note`, when A is rank-deficient. `sums`, when given, are A and B at `v`
// already (JacobianSums' or the streamed polish's last linearization there) and save the pass.
template <typename ModelType>
bool VariableCovariance(const ModelFitter<ModelType>& fitter, ceres::Problem* problem,
                        const Variables& v, Eigen::MatrixXd* covariance, std::string* note,
                        const SandwichSums* sums = nullptr) {
  const std::vector<bool> held = HeldVariables(fitter, v, note);
  if (sums != nullptr) return SandwichCovariance(sums->a, sums->b, held, covariance, note);
  Eigen::MatrixXd a, b;
  JacobianSums(fitter, problem, v, nullptr, &a, &b);
  return SandwichCovariance(a, b, held, covariance, note);
}

// d params / d variables at `v` (one row per model parameter), by automatic differentiation
// of the parameterization with Jets.
template <typename ModelType>
Eigen::MatrixXd ParamGradients(const ModelFitter<ModelType>& fitter, const Variables& v) {
  const int n = fitter.FreeVariables();
  double params[ModelType::kNumParams];
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> gradients(
      ModelType::kNumParams, n);
  ParamsAndGradients<ModelType>(fitter.options().grey_specular, v.d, v.s, v.shape, params,
                                gradients.data());
  return gradients;
}

// Standard errors of the model parameters by the delta method through the parameterization's
// Jacobian (automatic differentiation with Jets).
template <typename ModelType>
std::vector<double> ParamStderr(const ModelFitter<ModelType>& fitter, const Variables& v,
                                const Eigen::MatrixXd& covariance) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const int n = static_cast<int>(covariance.rows());
  const Eigen::MatrixXd gradients = ParamGradients(fitter, v);
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
    const Eigen::VectorXd gradient = gradients.row(p).transpose();
    bool depends_on_held = false;
    for (int k = 0; k < n; ++k) depends_on_held = depends_on_held || (held[k] && gradient[k] != 0);
    errors[p] = depends_on_held
                    ? kNaN
                    : std::sqrt(std::max(0.0, gradient.dot(finite_covariance * gradient)));
  }
  return errors;
}

}  // namespace brdf::fitters
