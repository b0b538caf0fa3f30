#include "fitters/select.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <optional>

#include "core/format.h"
#include "fitters/fit_samples.h"

namespace brdf::fitters {

const std::vector<std::string>& AutoCandidates() {
  static const std::vector<std::string> candidates = [] {
    std::vector<std::string> names;
    for (const ModelInfo& info : ModelRegistry()) {
      if (info.auto_candidate) names.push_back(info.name);
    }
    return names;
  }();
  return candidates;
}

FitResult SelectAndFit(const Measurement& measurement, const FitOptions& options,
                       Selection* selection, std::vector<FitResult>* all_fits) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  PreparedSamples prepared = PrepareSamples(measurement);
  const size_t sample_count = prepared.samples.size();
  // A large table: the candidates compete on the fit's own stratified subsample (BIC on a
  // subsample is still BIC, and every candidate sees the same samples), and only the winner is
  // polished on every sample. Small files, and callers that keep every fit, fit every candidate
  // on all samples.
  const bool on_subsample = all_fits == nullptr && options.max_samples > 0 &&
                            prepared.samples.size() > options.max_samples;
  PreparedSamples subsample;
  if (on_subsample) {
    subsample.samples = Subsample(prepared.samples, options.max_samples, options.seed);
    subsample.weighting = prepared.weighting;
    subsample.designed = prepared.designed;
  }
  const PreparedSamples& contest = on_subsample ? subsample : prepared;
  const size_t contest_count = contest.samples.size();
  // The candidates are fitted side by side: each fit's own parallel loops leave cores idle
  // between their solver steps, and no fit depends on another or on the thread count, so the
  // results, kept in candidate order, are those of fitting them one after another (an error is
  // the first candidate's in that order). Each candidate's optimum on the subsample is kept:
  // the winner's fit on every sample starts from it instead of running the multi-start again
  // on the same subsample (fit.h).
  const std::vector<std::string>& names = AutoCandidates();
  std::vector<std::optional<FitResult>> candidate_fits(names.size());
  std::vector<SubsampleOptimum> optima(names.size());
  std::vector<std::exception_ptr> errors(names.size());
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t{0}, names.size(), [&](size_t k) {
      try {
        candidate_fits[k].emplace(FitPreparedSamples(contest, names[k], options, &optima[k]));
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
  });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  std::vector<FitResult> fits;
  size_t best = 0;
  for (size_t k = 0; k < names.size(); ++k) {
    FitResult& fit = *candidate_fits[k];
    selection->candidates.push_back(
        {names[k], fit.bic, fit.metrics.rmse, fit.free_variables, fit.converged});
    // A clearly lower BIC wins; ties (to rounding) keep the earlier, simpler candidate. This
    // matters: blinn-phong and blinn-phong-exact span the same family of lobes (they differ
    // by a constant factor that rho_s absorbs), so they reach the same BIC.
    fits.push_back(std::move(fit));
    if (fits.size() > 1 && fits.back().bic < fits[best].bic - 1e-9 * std::abs(fits[best].bic)) {
      best = fits.size() - 1;
    }
  }
  if (on_subsample) {
    subsample.samples = std::vector<FitSample>();
    fits[best] = FitPreparedSamples(prepared, fits[best].model.name(), options, &optima[best]);
  }
  // The energy check and the diagnostics cost more than many fits of a small file: only the
  // chosen fit gets them, unless the caller keeps every fit.
  for (size_t k = 0; k < fits.size(); ++k) {
    if (k == best || all_fits != nullptr) FinishFit(prepared, &fits[k]);
  }
  Release(&prepared);
  const FitResult& chosen = fits[best];
  selection->chosen = chosen.model.name();
  const CandidateScore& winner = selection->candidates[best];  // its score in the contest
  const CandidateScore* lambert = &selection->candidates.front();
  // What the chosen model's first lobe brings, and the best earlier rung whose lobe brings
  // something else (a power-cosine lobe, for a microfacet one): the sentence compares with it.
  const ModelInfo& chosen_info = chosen.model.info();
  const CandidateScore* other = nullptr;
  if (chosen_info.has_lobe()) {
    for (size_t k = 0; k < best; ++k) {
      const ModelInfo& info = FindModel(selection->candidates[k].model);
      if (info.has_lobe() && info.lobes.front().adds != chosen_info.lobes.front().adds &&
          (other == nullptr || selection->candidates[k].bic < other->bic)) {
        other = &selection->candidates[k];
      }
    }
  }
  if (!chosen_info.has_lobe()) {
    selection->reason =
        "lambert has the lowest BIC: no lobe lowers the error enough to pay for its extra "
        "variables";
  } else if (other != nullptr) {
    selection->reason = Format(
        "%s has the lowest BIC (%.6g; best earlier lobe, %s, %.6g; lambert %.6g): "
        "%s the rmse from %.4g (%s) to %.4g sr^-1",
        selection->chosen.c_str(), winner.bic, other->model.c_str(), other->bic, lambert->bic,
        chosen_info.lobes.front().adds.c_str(), other->rmse, other->model.c_str(), winner.rmse);
  } else {
    selection->reason = Format(
        "%s has the lowest BIC (%.6g, lambert %.6g): %s the rmse from "
        "%.4g to %.4g sr^-1",
        selection->chosen.c_str(), winner.bic, lambert->bic, chosen_info.lobes.front().adds.c_str(),
        lambert->rmse, winner.rmse);
  }
  if (on_subsample) {
    selection->reason += " (BIC and rmse of every candidate on the same " +
                         std::to_string(contest_count) +
                         "-sample stratified subsample; the chosen model then fitted to all " +
                         std::to_string(sample_count) + ")";
  }
  FitResult result = fits[best];
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (all_fits != nullptr) *all_fits = std::move(fits);
  return result;
}

ModelFit FitModelOrAuto(const Measurement& measurement, const std::string& model,
                        const FitOptions& options) {
  if (model != "auto") return {FitModel(measurement, model, options), std::nullopt};
  Selection selection;
  FitResult fit = SelectAndFit(measurement, options, &selection);
  return {std::move(fit), std::move(selection)};
}

}  // namespace brdf::fitters
