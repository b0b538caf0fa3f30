#include "fitters/select.h"

#include <cmath>
#include <cstdio>
#include <optional>

namespace brdf::fitters {

const std::vector<std::string>& AutoCandidates() {
  static const std::vector<std::string> candidates = {"lambert", "phong", "blinn-phong",
                                                      "blinn-phong-exact"};
  return candidates;
}

FitResult SelectAndFit(const Measurement& measurement, const FitOptions& options,
                       Selection* selection, std::vector<FitResult>* all_fits) {
  std::optional<FitResult> best;
  double total_time = 0;
  for (const std::string& name : AutoCandidates()) {
    FitResult fit = FitModel(measurement, name, options);
    total_time += fit.time_s;
    selection->candidates.push_back(
        {name, fit.bic, fit.metrics.rmse, fit.free_variables, fit.converged});
    if (all_fits != nullptr) all_fits->push_back(fit);
    // A clearly lower BIC wins; ties (to rounding) keep the earlier, simpler candidate. This
    // matters: blinn-phong and blinn-phong-exact span the same family of lobes (they differ
    // by a constant factor that rho_s absorbs), so they reach the same BIC.
    if (!best || fit.bic < best->bic - 1e-9 * std::abs(best->bic)) best.emplace(std::move(fit));
  }
  selection->chosen = best->model.name();
  const CandidateScore* lambert = &selection->candidates.front();
  char reason[256];
  if (selection->chosen == "lambert") {
    std::snprintf(reason, sizeof(reason),
                  "lambert has the lowest BIC: no lobe lowers the error enough to pay for its "
                  "extra variables");
  } else {
    std::snprintf(reason, sizeof(reason),
                  "%s has the lowest BIC (%.6g, lambert %.6g): the lobe lowers the rmse from "
                  "%.4g to %.4g sr^-1",
                  selection->chosen.c_str(), best->bic, lambert->bic, lambert->rmse,
                  best->metrics.rmse);
  }
  selection->reason = reason;
  best->time_s = total_time;
  return std::move(*best);
}

}  // namespace brdf::fitters
