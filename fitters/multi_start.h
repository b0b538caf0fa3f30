// The multi-start (DESIGN §6): local minima are real — a lobe started too broad or too sharp
// settles on the diffuse floor or on one bright sample, and a microfacet lobe started with a
// metal's f0 can mistake a grazing Fresnel rise for a sharp peak. Every start of
// ModelFitter::Starts() is solved for a few iterations on a small subsample (each start only
// has to find its basin, not its optimum); the lowest cost wins.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/errors.h"
#include "fitters/model_fitter.h"
#include "fitters/solve.h"

namespace brdf::fitters {

// The best start's variables over `samples` (of a `designed` schedule or not: Starts); adds the
// iterations spent to `iterations`. Throws ComputeError when every start fails (a non-finite
// cost).
template <typename ModelType>
std::vector<double> BestStart(const ModelFitter<ModelType>& fitter,
                              const std::vector<FitSample>& samples, bool designed,
                              int* iterations) {
  const FitOptions& options = fitter.options();
  const std::vector<FitStart> starts = fitter.Starts(designed);
  const FitObjective<ModelType> objective(samples, options.loss, options.grey_specular,
                                          options.samples_per_block);
  // The starts are independent: solved side by side (each on Ceres' one thread, its batches in
  // parallel), then compared in their order, so the choice does not depend on the thread count.
  std::vector<std::vector<double>> trials(starts.size());
  std::vector<double> costs(starts.size());
  std::vector<int> start_iterations(starts.size());
  tbb::parallel_for(size_t{0}, starts.size(), [&](size_t k) {
    trials[k] = fitter.InitialGuess(samples, starts[k]);
    const ceres::Solver::Summary summary =
        SolveLeastSquares(objective, &trials[k], fitter.lower(), fitter.upper(),
                          std::min(options.start_iterations, options.max_iterations));
    start_iterations[k] = static_cast<int>(summary.iterations.size());
    costs[k] = summary.final_cost;
  });
  std::vector<double> best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < starts.size(); ++k) {
    *iterations += start_iterations[k];
    if (std::isfinite(costs[k]) && costs[k] < best_cost) {
      best_cost = costs[k];
      best = trials[k];
    }
  }
  if (!std::isfinite(best_cost)) throw ComputeError("every start of the fit failed");
  return best;
}

}  // namespace brdf::fitters
