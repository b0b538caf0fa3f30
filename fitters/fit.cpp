#include "fitters/fit.h"

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "core/deterministic_reduce.h"
#include "core/errors.h"
#include "core/text.h"
#include "energy/albedo.h"
#include "fitters/diagnostics.h"
#include "fitters/energy_bound.h"
#include "fitters/parallel_cost.h"
#include "fitters/parameterization.h"
#include "fitters/residual.h"

namespace brdf::fitters {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// |logistic variable| beyond which its derivative (< 1e-10) no longer informs the covariance.
constexpr double kSaturated = 23.0;
// Smallest eigenvalue of J^T J, relative to the largest, for the variables to count as
// identifiable.
constexpr double kRankTolerance = 1e-13;
// Samples each start of the multi-start is solved on.
constexpr size_t kStartSamples = 4000;
// Reweighting rounds of the robust fit on the subsample (fit, reweight, refit).
constexpr int kRobustRounds = 4;
// Samples per Ceres residual block, each a ParallelBatchCost of BatchResiduals: large enough to
// keep every thread busy inside one block, small enough that Ceres' scratch copy of a block's
// Jacobian stays a few MB.
constexpr size_t kSamplesPerSolverBlock = size_t{1} << 16;
// Samples per chunk of the deterministic sums of the fit metrics.
constexpr int64_t kMetricsGrain = 4096;

// The fitter's free variables (parameterization.h); s[0] alone when the lobe is grey.
struct Variables {
  double d[3] = {0, 0, 0};
  double s[3] = {0, 0, 0};
  double log_m[1] = {0};
};

template <typename ModelType>
class ModelFitter {
 public:
  ModelFitter(LobeKind kind, const FitOptions& options)
      : kind_(kind), options_(options), lobed_(kind != LobeKind::kNone) {}

  int FreeVariables() const { return lobed_ ? (options_.grey_specular ? 5 : 7) : 3; }

  std::vector<double> Params(const Variables& v) const {
    std::vector<double> params(ModelType::kNumParams);
    VariablesToParams<double>(kind_, options_.grey_specular, v.d, v.s, v.log_m, params.data());
    return params;
  }

  // Data-driven start for one trial exponent: rho_d from the diffuse floor, rho_s from the peak
  // height above it, both pulled inside the energy budget.
  Variables InitialGuess(const std::vector<FitSample>& samples, double exponent) const {
    Variables v;
    for (int c = 0; c < 3; ++c) {
      std::vector<double> values;
      values.reserve(samples.size());
      for (const FitSample& sample : samples) values.push_back(sample.value[c]);
      const size_t floor_rank = lobed_ ? values.size() / 5 : values.size() / 2;
      std::nth_element(values.begin(), values.begin() + floor_rank, values.end());
      const double floor_value = std::max(values[floor_rank], 0.0);
      const double peak = *std::max_element(values.begin(), values.end());
      double rho_d = std::clamp(kPi * floor_value, 1e-3, 0.9);
      if (!lobed_) {
        v.d[c] = Logit(rho_d);
        continue;
      }
      // The model's own value at the lobe peak (wi = wo = normal) per unit rho_s.
      double unit[models::LobedSlots::kNumParams] = {0, 0, 0, 1, 1, 1, exponent};
      const Vec3 normal(0, 0, 1);
      const double peak_per_rho_s = ModelType::template Eval<double>(unit, normal, normal)[0];
      const double rho_s = std::max(peak - rho_d / kPi, 1e-6) / peak_per_rho_s;
      const double q = std::clamp(LobeAlbedoAtNormal(kind_, exponent) * rho_s, 1e-6, 0.9);
      rho_d = std::min(rho_d, 0.99 * (1.0 - q));
      v.d[c] = Logit(rho_d / (1.0 - q));
      v.s[c] = Logit(q);
    }
    if (options_.grey_specular) v.s[0] = (v.s[0] + v.s[1] + v.s[2]) / 3.0;
    v.log_m[0] = std::log(exponent);
    return v;
  }

  // A least-squares problem over `samples`, which must outlive it. Robust losses act per
  // sample through Reweight, not per (batched) residual block.
  std::unique_ptr<ceres::Problem> BuildProblem(const std::vector<FitSample>& samples,
                                               Variables* v) const {
    auto problem = std::make_unique<ceres::Problem>();
    ceres::LossFunction* const loss = nullptr;
    const size_t block = static_cast<size_t>(options_.samples_per_block);
    const int s_size = options_.grey_specular ? 1 : 3;
    const std::vector<int32_t> block_sizes =
        lobed_ ? std::vector<int32_t>{3, s_size, 1} : std::vector<int32_t>{3};
    for (size_t solver_start = 0; solver_start < samples.size();
         solver_start += kSamplesPerSolverBlock) {
      const size_t solver_end = std::min(samples.size(), solver_start + kSamplesPerSolverBlock);
      std::vector<std::unique_ptr<ceres::CostFunction>> batches;
      for (size_t start = solver_start; start < solver_end; start += block) {
        const int count = static_cast<int>(std::min(block, solver_end - start));
        auto* residual = new BatchResidual<ModelType>(kind_, options_.grey_specular, options_.loss,
                                                      samples.data() + start, count);
        if (!lobed_) {
          batches.emplace_back(
              new ceres::AutoDiffCostFunction<BatchResidual<ModelType>, ceres::DYNAMIC, 3>(
                  residual, 3 * count));
        } else if (options_.grey_specular) {
          batches.emplace_back(
              new ceres::AutoDiffCostFunction<BatchResidual<ModelType>, ceres::DYNAMIC, 3, 1, 1>(
                  residual, 3 * count));
        } else {
          batches.emplace_back(
              new ceres::AutoDiffCostFunction<BatchResidual<ModelType>, ceres::DYNAMIC, 3, 3, 1>(
                  residual, 3 * count));
        }
      }
      auto* cost = new ParallelBatchCost(std::move(batches), block_sizes);
      if (!lobed_) {
        problem->AddResidualBlock(cost, loss, v->d);
      } else {
        problem->AddResidualBlock(cost, loss, v->d, v->s, v->log_m);
      }
    }
    const int d_size = 3;
    for (int k = 0; k < d_size; ++k) {
      problem->SetParameterLowerBound(v->d, k, -FitVariables::kLogisticBound);
      problem->SetParameterUpperBound(v->d, k, FitVariables::kLogisticBound);
    }
    if (lobed_) {
      for (int k = 0; k < s_size; ++k) {
        problem->SetParameterLowerBound(v->s, k, -FitVariables::kLogisticBound);
        problem->SetParameterUpperBound(v->s, k, FitVariables::kLogisticBound);
      }
      problem->SetParameterLowerBound(v->log_m, 0, std::log(FitVariables::kMinExponent));
      problem->SetParameterUpperBound(v->log_m, 0, std::log(FitVariables::kMaxExponent));
    }
    return problem;
  }

  ceres::Solver::Summary Solve(ceres::Problem* problem, int max_iterations) const {
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    solver_options.max_num_iterations = max_iterations;
    // One solver thread: the residual blocks evaluate themselves in parallel
    // (ParallelBatchCost), so the result does not depend on the thread count.
    solver_options.num_threads = 1;
    solver_options.function_tolerance = 1e-12;
    solver_options.gradient_tolerance = 1e-14;
    solver_options.parameter_tolerance = 1e-12;
    solver_options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, problem, &summary);
    return summary;
  }

  std::vector<double*> Blocks(Variables* v) const {
    if (!lobed_) return {v->d};
    return {v->d, v->s, v->log_m};
  }

  // Squared norm of each sample's (3-channel) weighted residual at `v`, from the same functor
  // Ceres differentiates.
  std::vector<double> SquaredResiduals(const std::vector<FitSample>& samples,
                                       const Variables& v) const {
    std::vector<double> squared(samples.size());
    tbb::parallel_for(size_t{0}, samples.size(), [&](size_t k) {
      const BatchResidual<ModelType> residual(kind_, options_.grey_specular, options_.loss,
                                              &samples[k], 1);
      double r[3];
      if (lobed_) {
        residual(v.d, v.s, v.log_m, r);
      } else {
        residual(v.d, r);
      }
      squared[k] = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    });
    return squared;
  }

  // Iteratively reweighted least squares for a robust loss rho (Huber or Cauchy, evaluated by
  // Ceres' own loss functions): each sample's residual is scaled by sqrt(rho'(s_i)) at the
  // current fit, s_i its squared residual norm. The loss acts per sample — a blind spot zeroes
  // one sample, not a whole residual block. The scale is 3 x the robust standard deviation
  // (1.4826 x median absolute residual), so inliers stay in the quadratic part.
  std::vector<FitSample> Reweight(const std::vector<FitSample>& samples, const Variables& v,
                                  double* scale) const {
    const std::vector<double> squared = SquaredResiduals(samples, v);
    if (*scale <= 0) {
      std::vector<double> norms(squared.size());
      double mean_square = 0;
      for (size_t k = 0; k < squared.size(); ++k) {
        norms[k] = std::sqrt(squared[k]);
        mean_square += squared[k];
      }
      const size_t middle = norms.size() / 2;
      std::nth_element(norms.begin(), norms.begin() + middle, norms.end());
      mean_square /= std::max<size_t>(1, squared.size());
      *scale =
          std::max(3.0 * 1.4826 * norms[middle], 1e-9 * std::max(std::sqrt(mean_square), 1e-12));
    }
    std::unique_ptr<ceres::LossFunction> loss;
    if (options_.robust == Robust::kHuber) {
      loss = std::make_unique<ceres::HuberLoss>(*scale);
    } else {
      loss = std::make_unique<ceres::CauchyLoss>(*scale);
    }
    std::vector<FitSample> weighted = samples;
    for (size_t k = 0; k < samples.size(); ++k) {
      double rho[3];
      loss->Evaluate(squared[k], rho);
      weighted[k].scale *= std::sqrt(std::max(rho[1], 0.0));
    }
    return weighted;
  }

  // Sandwich (Huber-White) covariance of the variables, A^-1 B A^-1 with A = sum J_i^T J_i
  // and B = sum J_i^T J_i r_i^2, accumulated in one parallel pass over the residual blocks. It
  // stays right when the weights or sigmas do not match the true noise. (ceres::Covariance
  // computes A^-1 by a sparse QR of the whole Jacobian: 4.9 s of an 8.9 s fit of a MERL table;
  // the 7x7 A from the same Jacobians costs one pass — docs/fitting.md.)
  //
  // A logistic variable pushed against its bound (a parameter at 0, an albedo budget used up)
  // has a vanishing derivative and would make A singular: such variables are held out, and
  // the parameters that depend on them are reported as "not available". A lobe share at its
  // lower bound in every channel means the lobe vanished; its exponent shapes nothing and is
  // held out too.
  bool Covariance(ceres::Problem* problem, const Variables& v, Eigen::MatrixXd* covariance,
                  std::string* note) const {
    std::vector<double*> blocks;
    std::vector<int> sizes;
    const int s_size = lobed_ ? (options_.grey_specular ? 1 : 3) : 0;
    Variables at = v;
    blocks.push_back(at.d);
    sizes.push_back(3);
    if (lobed_) {
      blocks.insert(blocks.end(), {at.s, at.log_m});
      sizes.insert(sizes.end(), {s_size, 1});
    }
    const int n = 3 + (lobed_ ? s_size + 1 : 0);
    std::vector<bool> held(n, false);
    bool lobe_vanished = lobed_;
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
          "lobe fitted to matte data leaves the exponent free)";
      return false;
    }
    const Eigen::MatrixXd a_inverse = eigen.eigenvectors() * values.cwiseInverse().asDiagonal() *
                                      eigen.eigenvectors().transpose();
    const Eigen::MatrixXd free_covariance = a_inverse * b * a_inverse;
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) (*covariance)(free[i], free[j]) = free_covariance(i, j);
    }
    return true;
  }

  // Standard errors of the model parameters by the delta method through the
  // parameterization's Jacobian (automatic differentiation with Jets).
  std::vector<double> ParamStderr(const Variables& v, const Eigen::MatrixXd& covariance) const {
    using Jet = ceres::Jet<double, 7>;
    const int n = static_cast<int>(covariance.rows());
    Jet d[3], s[3], log_m[1];
    int slot = 0;
    for (int c = 0; c < 3; ++c) d[c] = Jet(v.d[c], slot++);
    const int s_size = lobed_ ? (options_.grey_specular ? 1 : 3) : 0;
    for (int c = 0; c < s_size; ++c) s[c] = Jet(v.s[c], slot++);
    if (lobed_) log_m[0] = Jet(v.log_m[0], slot++);
    Jet params[ModelType::kNumParams];
    VariablesToParams<Jet>(kind_, options_.grey_specular, d, s, log_m, params);
    // Held (at-the-bound) variables carry NaN on the diagonal and zeros elsewhere; a
    // parameter that depends on one gets NaN, "not available".
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
      for (int k = 0; k < n; ++k)
        depends_on_held = depends_on_held || (held[k] && gradient[k] != 0);
      errors[p] = depends_on_held
                      ? kNaN
                      : std::sqrt(std::max(0.0, gradient.dot(finite_covariance * gradient)));
    }
    return errors;
  }

 private:
  LobeKind kind_;
  const FitOptions& options_;
  bool lobed_;
};

FitMetrics ComputeMetrics(const Model& model, const std::vector<FitSample>& samples) {
  struct Sums {
    double weight = 0, l2 = 0, log = 0, cosine = 0;
  };
  const Sums sums = DeterministicReduce(
      static_cast<int64_t>(samples.size()), kMetricsGrain, Sums{},
      [&](int64_t begin, int64_t end, Sums partial) {
        for (int64_t k = begin; k < end; ++k) {
          const FitSample& sample = samples[k];
          const Rgb f = model.Eval(sample.wi, sample.wo);
          const Rgb difference = f - sample.value;
          const double c = sample.cos_theta_i;
          const Rgb log_difference =
              (1.0 + f * c).log() - (1.0 + (sample.value * c).max(-0.999)).log();
          partial.weight += 3 * sample.weight;
          partial.l2 += sample.weight * difference.square().sum();
          partial.log += sample.weight * log_difference.square().sum();
          partial.cosine += sample.weight * (difference * c).square().sum();
        }
        return partial;
      },
      [](Sums a, const Sums& b) {
        a.weight += b.weight;
        a.l2 += b.l2;
        a.log += b.log;
        a.cosine += b.cosine;
        return a;
      });
  FitMetrics metrics;
  metrics.rmse = std::sqrt(sums.l2 / sums.weight);
  metrics.log_rmse = std::sqrt(sums.log / sums.weight);
  metrics.cosine_l2 = std::sqrt(sums.cosine / sums.weight);
  return metrics;
}

bool Converged(const ceres::Solver::Summary& summary) {
  return summary.termination_type == ceres::CONVERGENCE ||
         summary.termination_type == ceres::USER_SUCCESS;
}

template <typename ModelType>
FitResult RunFit(LobeKind kind, const ModelInfo& info, const PreparedSamples& prepared,
                 const FitOptions& options) {
  ModelFitter<ModelType> fitter(kind, options);
  const std::vector<FitSample>& all = prepared.samples;
  const std::vector<FitSample> subset = Subsample(all, options.max_samples, options.seed);
  const bool subsampled = subset.size() < all.size();

  // 1. Multi-start over the exponent on a smaller subsample (each start only has to find its
  // basin), without a robust loss.
  const std::vector<FitSample> start_subset =
      Subsample(subset, std::min<size_t>(subset.size(), kStartSamples), options.seed + 1);
  Variables best;
  double best_cost = std::numeric_limits<double>::infinity();
  const std::vector<double> starts =
      kind == LobeKind::kNone ? std::vector<double>{1.0} : options.start_exponents;
  int iterations = 0;
  for (double exponent : starts) {
    Variables trial = fitter.InitialGuess(start_subset, exponent);
    auto problem = fitter.BuildProblem(start_subset, &trial);
    const ceres::Solver::Summary summary =
        fitter.Solve(problem.get(), std::min(options.start_iterations, options.max_iterations));
    iterations += static_cast<int>(summary.iterations.size());
    if (std::isfinite(summary.final_cost) && summary.final_cost < best_cost) {
      best_cost = summary.final_cost;
      best = trial;
    }
  }
  if (!std::isfinite(best_cost)) throw ComputeError("every start of the fit failed");

  // 2. Refine the best start on the subsample. A robust loss re-estimates its scale from
  // each round's residuals: the first estimate is inflated by the bias the outliers caused.
  {
    auto problem = fitter.BuildProblem(subset, &best);
    iterations +=
        static_cast<int>(fitter.Solve(problem.get(), options.max_iterations).iterations.size());
    for (int round = 0; options.robust != Robust::kNone && round < kRobustRounds; ++round) {
      double scale = 0;  // estimated afresh
      const std::vector<FitSample> weighted = fitter.Reweight(subset, best, &scale);
      auto robust_problem = fitter.BuildProblem(weighted, &best);
      iterations += static_cast<int>(
          fitter.Solve(robust_problem.get(), options.max_iterations).iterations.size());
    }
  }

  // 3. Polish on every sample (the final solve, whose convergence is reported).
  Variables final_variables = best;
  std::vector<FitSample> final_samples;
  if (options.robust != Robust::kNone) {
    double scale = 0;
    final_samples = fitter.Reweight(all, best, &scale);
  }
  const std::vector<FitSample>& polish_samples =
      options.robust == Robust::kNone ? all : final_samples;
  auto problem = fitter.BuildProblem(polish_samples, &final_variables);
  const ceres::Solver::Summary summary = fitter.Solve(problem.get(), options.max_iterations);
  iterations += static_cast<int>(summary.iterations.size());

  std::vector<double> params = fitter.Params(final_variables);
  bool finite =
      std::all_of(params.begin(), params.end(), [](double p) { return std::isfinite(p); });
  if (!finite) {  // never return NaN: fall back to the subsample's optimum
    final_variables = best;
    params = fitter.Params(final_variables);
  }

  FitResult result(Model(info, params));
  result.loss = options.loss;
  result.robust = options.robust;
  result.samples = all.size();
  result.skipped = prepared.skipped_missing + prepared.skipped_invalid;
  result.weighting = prepared.weighting;
  result.converged = finite && Converged(summary);
  result.iterations = iterations;
  result.final_cost = summary.final_cost;
  result.termination = summary.BriefReport();
  result.free_variables = fitter.FreeVariables();
  result.metrics = ComputeMetrics(result.model, all);
  if (subsampled) {
    result.warnings.push_back("started from a stratified subsample of " +
                              std::to_string(subset.size()) + " samples, then polished on all " +
                              std::to_string(all.size()));
  }

  // Standard errors.
  Eigen::MatrixXd covariance;
  result.stderr_values.assign(params.size(), kNaN);
  if (fitter.Covariance(problem.get(), final_variables, &covariance, &result.stderr_note)) {
    result.stderr_values = fitter.ParamStderr(final_variables, covariance);
    result.stderr_available = true;
  }

  // Information criterion from the plain weighted residuals (the loss's, not the robust one).
  std::vector<double> residuals;
  ceres::Problem::EvaluateOptions evaluate_options;
  problem->Evaluate(evaluate_options, nullptr, &residuals, nullptr, nullptr);
  double rss = 0;
  for (double r : residuals) rss += r * r;
  const double n = static_cast<double>(residuals.size());
  result.bic = n * std::log(std::max(rss, 1e-300) / n) + result.free_variables * std::log(n);

  // Energy: the bound is built into the parameterization (closed form, energy_bound.h); the
  // report checks the fitted material independently with the albedo integrator of
  // `brdf energy` (DESIGN §7), over 90 incidence angles.
  const Model& model = result.model;
  Rgb bound = Rgb::Zero();
  for (int c = 0; c < 3; ++c) {
    bound[c] = model.Param("rho_d", c);
    if (kind != LobeKind::kNone) {
      bound[c] +=
          LobeAlbedoAtNormal(kind, params[models::LobedSlots::kExponent]) * model.Param("rho_s", c);
    }
  }
  const AlbedoCurve curve = ModelAlbedoCurve(model, AlbedoOptions{});
  result.energy.max_albedo = curve.max_albedo;
  result.energy.albedo_error = curve.error_at_max;
  result.energy.bound = bound;
  result.energy.theta_deg_at_max = curve.theta_deg_at_max;
  result.energy.conserving = curve.conserving();
  result.energy.method = std::string("albedo integrated over ") +
                         std::to_string(curve.points.size()) + " incidence angles (" +
                         AlbedoMethodName(curve.method) + "); bound rho_d + A(m) rho_s";
  for (int c = 0; c < 3; ++c) {
    if (bound[c] > 0.999) {
      result.warnings.push_back(std::string("energy bound active in channel ") + "rgb"[c] +
                                ": the data ask for an albedo of 1 or more");
    }
  }
  return result;
}

}  // namespace

Robust ParseRobust(const std::string& name) {
  if (name == "none") return Robust::kNone;
  if (name == "huber") return Robust::kHuber;
  if (name == "cauchy") return Robust::kCauchy;
  throw UsageError("unknown robust loss '" + name + "' (known: none, huber, cauchy)");
}

const char* RobustName(Robust robust) {
  switch (robust) {
    case Robust::kNone:
      return "none";
    case Robust::kHuber:
      return "huber";
    case Robust::kCauchy:
      return "cauchy";
  }
  return "?";
}

void FitOptions::Validate() const {
  if (max_iterations < 1) throw UsageError("max_iterations must be at least 1");
  if (samples_per_block < 1) throw UsageError("samples_per_block must be at least 1");
  if (max_samples != 0 && max_samples < 100) {
    throw UsageError("--max-samples must be 0 (all) or at least 100");
  }
  if (threads < 0) throw UsageError("--threads must not be negative");
  if (start_exponents.empty()) throw UsageError("at least one start exponent is needed");
  for (double exponent : start_exponents) {
    if (!(exponent >= FitVariables::kMinExponent && exponent <= FitVariables::kMaxExponent)) {
      throw UsageError("start exponents must lie in [1, 1e6]");
    }
  }
}

std::string FitResult::Summary() const {
  std::ostringstream line;
  line << model.ToString() << "  rmse " << metrics.rmse << " sr^-1, "
       << (converged ? "converged" : "NOT converged") << ", " << samples << " samples, " << time_s
       << " s";
  return line.str();
}

FitResult FitModel(const Measurement& measurement, const std::string& model_name,
                   const FitOptions& options) {
  options.Validate();
  // Ceres reports rank deficiency through glog warnings; the fit report says it in words.
  static const bool quiet_ceres = [] {
    FLAGS_minloglevel = google::GLOG_ERROR;
    return true;
  }();
  (void)quiet_ceres;
  const auto start = std::chrono::steady_clock::now();
  const LobeKind kind = LobeKindOf(model_name);
  const ModelInfo& info = FindModel(model_name);
  const PreparedSamples prepared = PrepareSamples(measurement, options.loss);
  // Every parallel loop of the fit runs in an arena of `threads` workers; no result depends on
  // their number.
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  FitResult result = arena.execute([&] {
    return VisitModelType(model_name, [&](auto model_type) {
      return RunFit<decltype(model_type)>(kind, info, prepared, options);
    });
  });
  AppendFitDiagnostics(measurement, prepared, &result);  // docs/stability.md
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace brdf::fitters
