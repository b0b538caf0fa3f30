// The fit of one model type (a composition, models/composition.h): what FitPreparedSamples runs
// for the model it is named, and what a caller with a composition of its own (a test of a new
// term) runs directly. Steps: the multi-start and refinement on a stratified subsample
// (FitSubsample), then the polish on every sample, standard errors and the information criterion
// (FitComposition); fit.cpp adds the energy check and the diagnostics (FinishFit).
#pragma once

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "fitters/covariance.h"
#include "fitters/fit.h"
#include "fitters/model_fitter.h"
#include "fitters/multi_start.h"
#include "fitters/reading_nodes.h"
#include "fitters/solve.h"

namespace brdf::fitters {

// Whether Ceres says the solve converged.
bool Converged(const ceres::Solver::Summary& summary);

namespace fit_detail {
// Samples each start of the multi-start is solved on.
inline constexpr size_t kStartSamples = 4000;
// Reweighting rounds of the robust fit on the subsample (fit, reweight, refit).
inline constexpr int kRobustRounds = 4;
// Polishes at most: the first at the subsample's optimum, then from each polished optimum while
// the instrument's nodes change (reading_nodes.h), and at least once more with weights from a
// polished optimum (VarianceFunction).
inline constexpr int kPolishRounds = 4;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Samples per chunk of the deterministic sums of the fit metrics.
inline constexpr int64_t kMetricsGrain = 4096;
}  // namespace fit_detail

// Solid-angle-weighted means of the fit metrics over the objective's samples and channels, with
// the model's values from the objective at `at`.
template <typename M>
FitMetrics ComputeMetrics(const FitObjective<M>& objective,
                          const typename FitObjective<M>::Point& at) {
  const std::vector<FitSample>& samples = objective.samples();
  struct Sums {
    double weight = 0, l2 = 0, log = 0, cosine = 0;
  };
  const Sums sums = DeterministicReduce(
      static_cast<int64_t>(samples.size()), fit_detail::kMetricsGrain, Sums{},
      [&](int64_t begin, int64_t end, Sums partial) {
        const auto prepared = objective.Prepare(at);
        for (int64_t k = begin; k < end; ++k) {
          const FitSample& sample = samples[k];
          const Rgb f = objective.Value(at, prepared, k);
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

// The sandwich's middle term B clustered by incidence: the sum over incidences of s s^T, s the
// sum of J^T r over the incidence's rows, times G / (G - 1) for G incidences. An instrument's
// light arm turns all the readings of an incidence at once, and its detector arm a reading's
// three channels at once, so their residuals move together; B as a sum of per-row squares
// (objective.h) takes them as independent and understates the spread of fits. (Cameron &
// Miller 2015, "A practitioner's guide to cluster-robust inference", for the estimator and
// its small-sample factor.)
template <typename ModelType>
Eigen::MatrixXd IncidenceClusteredB(const FitObjective<ModelType>& objective,
                                    const typename FitObjective<ModelType>::Point& at,
                                    const std::vector<FitSample>& samples) {
  int count = 0;
  const std::vector<int> group = IncidenceGroups(samples, &count);
  const int n = objective.NumVariables();
  std::vector<Eigen::VectorXd> scores(count, Eigen::VectorXd::Zero(n));
  objective.ForEachRow(at, [&](int64_t row, const Eigen::VectorXd& jacobian, double residual) {
    scores[group[static_cast<size_t>(row / 3)]] += jacobian * residual;
  });
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, n);
  for (const Eigen::VectorXd& score : scores) b += score * score.transpose();
  return count > 1 ? Eigen::MatrixXd(b * (count / (count - 1.0))) : b;
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
  const std::vector<FitSample> start_subset = Subsample(
      subset, std::min<size_t>(subset.size(), fit_detail::kStartSamples), options.seed + 1);
  std::vector<double>& best = optimum.variables;
  best = BestStart(fitter, start_subset, designed, &optimum.iterations);

  // 2. Refine the best start on the subsample. A robust loss re-estimates its scale from
  // each round's residuals: the first estimate is inflated by the bias the outliers caused.
  const auto solve = [&](const std::vector<FitSample>& samples) {
    const FitObjective<ModelType> objective(samples, options.loss, options.grey_specular,
                                            options.samples_per_block);
    optimum.iterations += static_cast<int>(
        SolveLeastSquares(objective, &best, fitter.lower(), fitter.upper(), options.max_iterations)
            .iterations.size());
  };
  solve(subset);
  for (int round = 0; options.robust != Robust::kNone && round < fit_detail::kRobustRounds;
       ++round) {
    double scale = 0;  // estimated afresh
    solve(fitter.Reweight(subset, best, &scale));
  }
  return optimum;
}

template <typename ModelType>
FitResult FitComposition(const ModelInfo& info, const PreparedSamples& prepared,
                         const FitOptions& options, SubsampleOptimum* given) {
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
  const std::vector<double>& best = optimum.variables;
  int iterations = optimum.iterations;

  // 3. Polish on every sample (the final solve, whose convergence is reported), with the
  // robust weights of the subsample's optimum. Through the measurement's instrument
  // (reading_nodes.h) and with weights from sigmas the model predicts (VarianceFunction), both
  // made at the current point: the polish is repeated from its optimum until the nodes no
  // longer change and the weights have been predicted from a polished optimum.
  std::vector<FitSample> weighted;
  if (options.robust != Robust::kNone) {
    double scale = 0;
    weighted = fitter.Reweight(all, best, &scale);
  }
  const std::vector<FitSample>& robust_samples = options.robust == Robust::kNone ? all : weighted;
  const bool model_weights = !prepared.sigma.empty();
  const VarianceFunction variance =
      model_weights ? FitVarianceFunction(prepared) : VarianceFunction{};
  std::vector<FitSample> model_weighted;
  SampleNodes nodes;
  const gonio::Instrument* instrument = prepared.instrument.get();
  std::vector<double> final_variables = best;
  std::unique_ptr<FitObjective<ModelType>> objective_holder;
  NormalSums sums;
  bool have_sums = false;
  ceres::Solver::Summary summary;
  for (int round = 0; round < fit_detail::kPolishRounds; ++round) {
    const Model current(info, fitter.Params(final_variables));
    if (instrument != nullptr) {
      SampleNodes next = InstrumentNodes(*instrument, current, robust_samples);
      if (round >= 2 && next.SameLayout(nodes)) break;
      nodes = std::move(next);
    } else if (round >= (model_weights ? 2 : 1)) {
      break;
    }
    if (model_weights) {
      std::vector<Rgb> predicted(all.size());
      tbb::parallel_for(size_t{0}, all.size(), [&](size_t k) {
        predicted[k] =
            PredictReading(current, robust_samples, instrument != nullptr ? &nodes : nullptr, k);
      });
      model_weighted = ModelWeighted(robust_samples, prepared.sigma, variance, predicted);
    }
    objective_holder = std::make_unique<FitObjective<ModelType>>(
        model_weights ? model_weighted : robust_samples, options.loss, options.grey_specular,
        options.samples_per_block, instrument != nullptr ? &nodes : nullptr);
    have_sums = false;
    std::vector<double> variables = final_variables;
    summary = SolveLeastSquares(*objective_holder, &variables, fitter.lower(), fitter.upper(),
                                options.max_iterations, &sums, &have_sums);
    iterations += static_cast<int>(summary.iterations.size());
    if (!std::all_of(variables.begin(), variables.end(),
                     [](double v) { return std::isfinite(v); })) {
      have_sums = false;
      break;
    }
    final_variables = variables;
  }
  const FitObjective<ModelType>& objective = *objective_holder;
  const std::vector<FitSample>& polish_samples = objective.samples();

  std::vector<double> params = fitter.Params(final_variables);
  bool finite =
      std::all_of(params.begin(), params.end(), [](double p) { return std::isfinite(p); });
  if (!finite) {  // never return NaN: fall back to the subsample's optimum
    final_variables = best;
    params = fitter.Params(final_variables);
    have_sums = false;
  }

  FitResult result(Model(info, params));
  result.loss = options.loss;
  result.robust = options.robust;
  result.samples = all.size();
  result.skipped = prepared.skipped_missing + prepared.skipped_invalid;
  result.weighting = prepared.weighting;
  if (model_weights) result.weighting += "; sigma predicted from the model (iteratively)";
  if (instrument != nullptr) {
    result.weighting += "; readings predicted through the instrument's apertures (" +
                        std::to_string(nodes.points_per_reading) + "-point quadrature on " +
                        std::to_string(nodes.averaged) + " samples near a lobe)";
  }
  result.converged = finite && Converged(summary);
  result.iterations = iterations;
  result.final_cost = summary.final_cost;
  result.termination = summary.BriefReport();
  result.free_variables = fitter.FreeVariables();
  const typename FitObjective<ModelType>::Point at = objective.At(final_variables.data());
  result.metrics = ComputeMetrics(objective, at);
  if (subsampled) {
    result.warnings.push_back("started from a stratified subsample of " +
                              std::to_string(subset_size) + " samples, then polished on all " +
                              std::to_string(all.size()));
  }

  // Standard errors (covariance.h) and the information criterion, from one pass of the sums at
  // the final variables; the criterion from the plain weighted residuals (the loss's, not the
  // robust one).
  if (!have_sums) sums = objective.Sums(at);
  if (instrument != nullptr && instrument->jitter_deg > 0) {
    sums.b = IncidenceClusteredB(objective, at, polish_samples);
  }
  Eigen::MatrixXd covariance;
  result.stderr_values.assign(params.size(), fit_detail::kNaN);
  if (VariableCovariance<ModelType>(options.grey_specular, final_variables, sums, &covariance,
                                    &result.stderr_note)) {
    result.stderr_values = ParamStderr<ModelType>(at, covariance);
    result.stderr_available = true;
  }
  const double rss = 2 * sums.cost;
  const double n = 3.0 * static_cast<double>(polish_samples.size());
  result.bic = n * std::log(std::max(rss, 1e-300) / n) + result.free_variables * std::log(n);
  return result;
}

}  // namespace brdf::fitters
