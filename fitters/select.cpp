#include "fitters/select.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>

#include "core/format.h"
#include "fitters/fit_samples.h"
#include "fitters/image_error.h"

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

namespace {

// The candidate whose sphere is closest to the measurement's (select.h), its image errors filled
// in: the simplest within kImageErrorTolerance of the lowest.
size_t ChooseByImage(const TabulatedBrdf& measured, const std::vector<FitResult>& fits,
                     std::vector<CandidateScore>* candidates) {
  const SphereRadiance reference =
      RenderLitSphere([&](const Vec3& wi, const Vec3& wo) { return measured.Eval(wi, wo); });
  double lowest = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < fits.size(); ++k) {
    const Model& model = fits[k].model;
    const double error = RelativeL1(reference, RenderLitSphere([&](const Vec3& wi, const Vec3& wo) {
                                      return model.Eval(wi, wo);
                                    }));
    (*candidates)[k].image_error = error;
    if (std::isfinite(error)) lowest = std::min(lowest, error);
  }
  for (size_t k = 0; k < fits.size(); ++k) {
    if ((*candidates)[k].image_error <= lowest * (1.0 + kImageErrorTolerance)) return k;
  }
  return 0;
}

// Why BIC prefers the candidate `index` (of the candidates, simplest first), with the loss's rms
// residual, which BIC weighs: a lower BIC at no fewer variables is a lower rms residual.
std::string BicReason(const ModelInfo& info, size_t index, const Selection& selection) {
  const CandidateScore& winner = selection.candidates[index];
  const CandidateScore& lambert = selection.candidates.front();
  if (!info.has_lobe()) {
    return Format(
        "lambert has the lowest BIC (%.6g): no lobe lowers the loss's rms residual (%.4g) enough "
        "to pay for its extra variables",
        winner.bic, winner.loss_rms);
  }
  // A second lobe: the sentence compares with the earlier rung of the first lobe alone.
  if (info.lobes.size() > 1) {
    for (size_t k = 0; k < index; ++k) {
      const ModelInfo& earlier = FindModel(selection.candidates[k].model);
      if (earlier.diffuse == info.diffuse && earlier.lobes.size() == 1 &&
          earlier.lobes.front().term == info.lobes.front().term) {
        const CandidateScore& single = selection.candidates[k];
        return Format(
            "%s has the lowest BIC (%.6g; one lobe, %s, %.6g; lambert %.6g): a second %s lobe "
            "lowers the loss's rms residual from %.4g (%s) to %.4g",
            winner.model.c_str(), winner.bic, single.model.c_str(), single.bic, lambert.bic,
            info.lobes[1].term.c_str(), single.loss_rms, single.model.c_str(), winner.loss_rms);
      }
    }
  }
  // The best earlier rung whose lobe brings something else (a power-cosine lobe, for a
  // microfacet one): the sentence compares with it.
  const CandidateScore* other = nullptr;
  for (size_t k = 0; k < index; ++k) {
    const ModelInfo& earlier = FindModel(selection.candidates[k].model);
    if (earlier.has_lobe() && earlier.lobes.front().adds != info.lobes.front().adds &&
        (other == nullptr || selection.candidates[k].bic < other->bic)) {
      other = &selection.candidates[k];
    }
  }
  const char* adds = info.lobes.front().adds.c_str();
  if (other != nullptr) {
    return Format(
        "%s has the lowest BIC (%.6g; best earlier lobe, %s, %.6g; lambert %.6g): %s the loss's "
        "rms residual from %.4g (%s) to %.4g",
        winner.model.c_str(), winner.bic, other->model.c_str(), other->bic, lambert.bic, adds,
        other->loss_rms, other->model.c_str(), winner.loss_rms);
  }
  return Format(
      "%s has the lowest BIC (%.6g, lambert %.6g): %s the loss's rms residual from %.4g to %.4g",
      winner.model.c_str(), winner.bic, lambert.bic, adds, lambert.loss_rms, winner.loss_rms);
}

// Why the image chose `index`, against BIC's choice and the runner-up.
std::string ImageReason(size_t index, size_t bic_index, const Selection& selection) {
  const CandidateScore& chosen = selection.candidates[index];
  std::string reason = Format(
      "%s renders closest to the measurement: image error %.4g (relative L1 of the lit sphere "
      "under lights at 20 and 60 deg",
      chosen.model.c_str(), chosen.image_error);
  const CandidateScore* next = nullptr;
  for (const CandidateScore& candidate : selection.candidates) {
    if (&candidate != &chosen && (next == nullptr || candidate.image_error < next->image_error)) {
      next = &candidate;
    }
  }
  if (index != bic_index) {
    const CandidateScore& by_bic = selection.candidates[bic_index];
    reason += Format("; %s, BIC's choice, %.4g", by_bic.model.c_str(), by_bic.image_error);
  }
  if (next != nullptr && next->model != selection.candidates[bic_index].model) {
    reason += Format("; next, %s, %.4g", next->model.c_str(), next->image_error);
  }
  if (next != nullptr && next->image_error < chosen.image_error) {
    reason +=
        Format("; within %.0f %% of the lowest, the simplest is kept", 100 * kImageErrorTolerance);
  }
  return reason + ")";
}

}  // namespace

FitResult SelectAndFit(const Measurement& measurement, const FitOptions& given_options,
                       Selection* selection, std::vector<FitResult>* all_fits) {
  given_options.Validate();
  const auto start = std::chrono::steady_clock::now();
  FitOptions options = given_options;
  options.loss = ResolveLoss(given_options.loss, measurement);
  PreparedSamples prepared = PrepareSamples(measurement, options.loss);
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
  InFitArena(options.threads, [&] {
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
    const double n = 3.0 * static_cast<double>(fit.samples);
    selection->candidates.push_back(
        {names[k], fit.bic, fit.metrics.rmse, std::sqrt(2.0 * fit.final_cost / std::max(n, 1.0)),
         std::numeric_limits<double>::quiet_NaN(), fit.free_variables, fit.converged});
    // A clearly lower BIC wins; ties (to rounding) keep the earlier, simpler candidate.
    fits.push_back(std::move(fit));
    if (fits.size() > 1 && fits.back().bic < fits[best].bic - 1e-9 * std::abs(fits[best].bic)) {
      best = fits.size() - 1;
    }
  }
  const size_t bic_best = best;
  if (measurement.tabulated) {
    selection->criterion = "image";
    best = ChooseByImage(*measurement.tabulated, fits, &selection->candidates);
  }
  if (on_subsample) {
    subsample.samples = std::vector<FitSample>();
    fits[best] = FitPreparedSamples(prepared, fits[best].model.name(), options, &optima[best]);
  }
  // The energy check and the diagnostics cost more than many fits of a small file: only the
  // chosen fit gets them, unless the caller keeps every fit. A lobed fit's diagnostics compare
  // it with its diffuse term alone on every sample, which a candidate fitted on every sample
  // already is.
  const auto diffuse_candidate = [&](const FitResult& fit) -> const FitResult* {
    if (on_subsample) return nullptr;
    for (const FitResult& candidate : fits) {
      if (candidate.model.name() == fit.model.info().diffuse) return &candidate;
    }
    return nullptr;
  };
  for (size_t k = 0; k < fits.size(); ++k) {
    if (k == best || all_fits != nullptr) {
      FinishFit(prepared, options, &fits[k], diffuse_candidate(fits[k]));
    }
  }
  Release(&prepared);
  const FitResult& chosen = fits[best];
  selection->chosen = chosen.model.name();
  selection->reason = BicReason(fits[bic_best].model.info(), bic_best, *selection);
  if (selection->criterion == "image") {
    selection->reason =
        ImageReason(best, bic_best, *selection) + "; by BIC alone, " + selection->reason;
  }
  if (on_subsample) {
    selection->reason += " (every candidate on the same " + std::to_string(contest_count) +
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
