#include "fitters/fit.h"

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "core/deterministic_reduce.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/text.h"
#include "fitters/covariance.h"
#include "fitters/diagnostics.h"
#include "fitters/energy_check.h"
#include "fitters/gram_solve.h"
#include "fitters/model_fitter.h"
#include "fitters/multi_start.h"
#include "fitters/streamed_polish.h"

namespace brdf::fitters {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Samples each start of the multi-start is solved on.
constexpr size_t kStartSamples = 4000;
// Reweighting rounds of the robust fit on the subsample (fit, reweight, refit).
constexpr int kRobustRounds = 4;
// Samples per chunk of the deterministic sums of the fit metrics.
constexpr int64_t kMetricsGrain = 4096;

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
          const double c = sample.cos_theta_i();
          const Rgb log_difference = (1.0 + f * c).log() - LossTarget(Loss::kLog, sample.value, c);
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

// Steps 1 and 2 of a fit on the stratified subsample `subset` (of a `designed` schedule or
// not: ModelFitter::Starts): the multi-start and the refinement of its best start
// (SubsampleOptimum).
template <typename ModelType>
SubsampleOptimum FitSubsample(const ModelFitter<ModelType>& fitter,
                              const std::vector<FitSample>& subset, bool designed) {
  const FitOptions& options = fitter.options();
  SubsampleOptimum optimum;
  optimum.found = true;
  // 1. Multi-start (multi_start.h) on a smaller subsample, without a robust loss.
  const std::vector<FitSample> start_subset =
      Subsample(subset, std::min<size_t>(subset.size(), kStartSamples), options.seed + 1);
  Variables& best = optimum.variables;
  best = BestStart(fitter, start_subset, designed, &optimum.iterations);

  // 2. Refine the best start on the subsample. A robust loss re-estimates its scale from
  // each round's residuals: the first estimate is inflated by the bias the outliers caused.
  optimum.iterations += static_cast<int>(
      SolveLeastSquares(fitter, subset, &best, options.max_iterations).iterations.size());
  for (int round = 0; options.robust != Robust::kNone && round < kRobustRounds; ++round) {
    double scale = 0;  // estimated afresh
    const std::vector<FitSample> weighted = fitter.Reweight(subset, best, &scale);
    optimum.iterations += static_cast<int>(
        SolveLeastSquares(fitter, weighted, &best, options.max_iterations).iterations.size());
  }
  return optimum;
}

template <typename ModelType>
FitResult RunFit(const ModelInfo& info, const PreparedSamples& prepared, const FitOptions& options,
                 SubsampleOptimum* given) {
  const ModelFitter<ModelType> fitter(options);
  const std::vector<FitSample>& all = prepared.samples;
  // Subsample keeps every sample of a set no larger than max_samples.
  const bool subsampled = options.max_samples != 0 && all.size() > options.max_samples;
  const size_t subset_size = subsampled ? options.max_samples : all.size();
  SubsampleOptimum optimum;
  if (given != nullptr && given->found) {
    optimum = *given;
  } else {
    optimum =
        FitSubsample(fitter, Subsample(all, options.max_samples, options.seed), prepared.designed);
    if (given != nullptr) *given = optimum;
  }
  const Variables& best = optimum.variables;
  int iterations = optimum.iterations;

  // 3. Polish on every sample (the final solve, whose convergence is reported).
  Variables final_variables = best;
  std::vector<FitSample> final_samples;
  if (options.robust != Robust::kNone) {
    double scale = 0;
    final_samples = fitter.Reweight(all, best, &scale);
  }
  const std::vector<FitSample>& polish_samples =
      options.robust == Robust::kNone ? all : final_samples;
  // On a subsampled (large) table the polish sums the normal equations instead of storing the
  // Jacobian (streamed_polish.h); small sets Ceres' solver (through GramCost, gram_solve.h).
  auto problem = fitter.BuildProblem(polish_samples, &final_variables);
  PolishSummary polish;
  if (subsampled) {
    polish = StreamedPolish(fitter, problem.get(), &final_variables, options.max_iterations);
  } else {
    const ceres::Solver::Summary summary =
        SolveLeastSquares(fitter, polish_samples, &final_variables, options.max_iterations);
    polish.iterations = static_cast<int>(summary.iterations.size());
    polish.initial_cost = summary.initial_cost;
    polish.final_cost = summary.final_cost;
    polish.converged = Converged(summary);
    polish.report = summary.BriefReport();
  }
  iterations += polish.iterations;

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
  result.converged = finite && polish.converged;
  result.iterations = iterations;
  result.final_cost = polish.final_cost;
  result.termination = polish.report;
  result.free_variables = fitter.FreeVariables();
  result.metrics = ComputeMetrics(result.model, all);
  if (subsampled) {
    result.warnings.push_back("started from a stratified subsample of " +
                              std::to_string(subset_size) + " samples, then polished on all " +
                              std::to_string(all.size()));
  }

  // Standard errors (covariance.h), from the streamed polish's last sums when they are at the
  // final variables.
  Eigen::MatrixXd covariance;
  result.stderr_values.assign(params.size(), kNaN);
  const SandwichSums* sums = finite && polish.sums_at_end ? &polish.sums : nullptr;
  if (VariableCovariance(fitter, problem.get(), final_variables, &covariance, &result.stderr_note,
                         sums)) {
    result.stderr_values = ParamStderr(fitter, final_variables, covariance);
    result.stderr_available = true;
  }

  // Information criterion from the plain weighted residuals (the loss's, not the robust one).
  double rss = 0;
  if (subsampled) {  // without the vector of every residual
    rss = 2 * HalfSquaredSum(fitter, problem.get(), final_variables);
  } else {
    std::vector<double> residuals;
    ceres::Problem::EvaluateOptions evaluate_options;
    problem->Evaluate(evaluate_options, nullptr, &residuals, nullptr, nullptr);
    for (double r : residuals) rss += r * r;
  }
  const double n = 3.0 * static_cast<double>(polish_samples.size());
  result.bic = n * std::log(std::max(rss, 1e-300) / n) + result.free_variables * std::log(n);
  return result;
}

}  // namespace

constexpr EnumName<Robust> kRobustNames[] = {
    {Robust::kNone, "none"},
    {Robust::kHuber, "huber"},
    {Robust::kCauchy, "cauchy"},
};

Robust ParseRobust(const std::string& name) { return ParseEnum(kRobustNames, name, "robust loss"); }

const char* RobustName(Robust robust) { return NameOf(kRobustNames, robust); }

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
  if (start_alphas.empty()) throw UsageError("at least one start alpha is needed");
  for (double alpha : start_alphas) {
    if (!(alpha >= FitVariables::kMinAlpha && alpha <= FitVariables::kMaxAlpha)) {
      throw UsageError("start alphas must lie in [0.001, 1.5]");
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

FitResult FitPreparedSamples(const PreparedSamples& prepared, const std::string& model_name,
                             const FitOptions& options, SubsampleOptimum* optimum) {
  options.Validate();
  // Ceres reports rank deficiency through glog warnings; the fit report says it in words.
  static const bool quiet_ceres = [] {
    FLAGS_minloglevel = google::GLOG_ERROR;
    return true;
  }();
  (void)quiet_ceres;
  const auto start = std::chrono::steady_clock::now();
  const ModelInfo& info = FindModel(model_name);
  // Every parallel loop of the fit runs in an arena of `threads` workers; no result depends on
  // their number.
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  FitResult result = arena.execute([&] {
    return VisitModelType(model_name, [&](auto model_type) {
      return RunFit<decltype(model_type)>(info, prepared, options, optimum);
    });
  });
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

void FinishFit(const PreparedSamples& prepared, FitResult* result) {
  const auto start = std::chrono::steady_clock::now();
  CheckFitEnergy(result);
  AppendFitDiagnostics(prepared, result);  // docs/stability.md
  result->time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

FitResult FitModel(const Measurement& measurement, const std::string& model_name,
                   const FitOptions& options) {
  options.Validate();
  FindModel(model_name);  // an unknown name is a usage error before any work
  const auto start = std::chrono::steady_clock::now();
  PreparedSamples prepared = PrepareSamples(measurement);
  FitResult result = FitPreparedSamples(prepared, model_name, options);
  FinishFit(prepared, &result);
  Release(&prepared);
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace brdf::fitters
