// --model auto: fit every candidate and keep the simplest one the data support (DESIGN §6,
// "model no more than the scene needs").
//
// Data that can be rendered (a reader's evaluator: MERL, RGL-EPFL; Measurement::tabulated) are
// judged the way a user sees a fit: every candidate's sphere against the measurement's own under
// directional lights (image_error.h), after Bieron & Peers, "An adaptive BRDF fitting metric",
// CGF 39(4) 2020, who select a fit's metric by how its renders compare. The candidate with the
// lowest image error is chosen, or the simplest one within 2 % of it. BIC, on the loss's
// residuals, can prefer a lobe the image does not want: a sharp lobe that buys the loss many
// samples near the mirror direction can cost the rendered sphere more than it brings.
//
// The criterion is the Bayesian information criterion, BIC = n ln(RSS/n) + k ln(n) (Schwarz
// 1978), over the n weighted residuals and k free variables. Why BIC rather than held-out
// error: it needs one fit per candidate instead of one per fold, and its ln(n) penalty grows
// with the sample count, so with the hundreds of thousands of samples of a MERL table a lobe
// must buy a real error reduction to be kept; on matte data a lobe with rho_s ~ 0 adds four
// variables and almost nothing else, and lambert wins.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "fitters/fit.h"

namespace brdf::fitters {

struct CandidateScore {
  std::string model;
  double bic = 0;
  double rmse = 0;      // of f, sr^-1 (FitMetrics)
  double loss_rms = 0;  // of the loss's weighted residuals, what BIC weighs: sqrt(RSS / n)
  double image_error = std::numeric_limits<double>::quiet_NaN();  // NaN without an evaluator
  int free_variables = 0;
  bool converged = false;
};

// A candidate within this relative margin of the lowest image error is as good: the simplest
// such one is chosen.
inline constexpr double kImageErrorTolerance = 0.02;

struct Selection {
  std::string criterion = "bic";  // or "image" (the measurement has an evaluator)
  std::string chosen;
  std::string reason;
  std::vector<CandidateScore> candidates;
};

// The candidates, simplest first.
const std::vector<std::string>& AutoCandidates();

// Fits every candidate; returns the chosen fit and fills `selection`. `all_fits`, when given,
// receives every candidate's fit in AutoCandidates() order.
FitResult SelectAndFit(const Measurement& measurement, const FitOptions& options,
                       Selection* selection, std::vector<FitResult>* all_fits = nullptr);

// What `--model M|auto` means, in one place for `brdf fit`, `brdf batch` and the Python module:
// "auto" runs SelectAndFit and returns its Selection; a model name runs FitModel (no selection).
struct ModelFit {
  FitResult fit;
  std::optional<Selection> selection;

  const Selection* selection_or_null() const { return selection ? &*selection : nullptr; }
};
ModelFit FitModelOrAuto(const Measurement& measurement, const std::string& model,
                        const FitOptions& options);

}  // namespace brdf::fitters
