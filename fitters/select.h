// --model auto: fit every candidate and keep the simplest one the data support (DESIGN §6,
// "model no more than the scene needs").
//
// The criterion is the Bayesian information criterion, BIC = n ln(RSS/n) + k ln(n) (Schwarz
// 1978), over the n weighted residuals and k free variables. Why BIC rather than held-out
// error: it needs one fit per candidate instead of one per fold, and its ln(n) penalty grows
// with the sample count, so with the hundreds of thousands of samples of a MERL table a lobe
// must buy a real error reduction to be kept; on matte data a lobe with rho_s ~ 0 adds four
// variables and almost nothing else, and lambert wins.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fitters/fit.h"

namespace brdf::fitters {

struct CandidateScore {
  std::string model;
  double bic = 0;
  double rmse = 0;
  int free_variables = 0;
  bool converged = false;
};

struct Selection {
  std::string criterion = "bic";
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
