// The multi-start (DESIGN §6): local minima are real — a lobe started too broad or too sharp
// settles on the diffuse floor or on one bright sample, and a microfacet lobe started with a
// metal's f0 can mistake a grazing Fresnel rise for a sharp peak. Every start of
// ModelFitter::Starts() is solved for a few iterations on a small subsample (each start only
// has to find its basin, not its optimum); the lowest cost wins.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/errors.h"
#include "fitters/model_fitter.h"

namespace brdf::fitters {

// The best start's variables over `samples` (of a `designed` schedule or not: Starts); adds the
// iterations spent to `iterations`. Throws ComputeError when every start fails (a non-finite
// cost).
template <typename ModelType>
Variables BestStart(const ModelFitter<ModelType>& fitter, const std::vector<FitSample>& samples,
                    bool designed, int* iterations) {
  const FitOptions& options = fitter.options();
  Variables best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (const FitStart& start : fitter.Starts(designed)) {
    Variables trial = fitter.InitialGuess(samples, start);
    auto problem = fitter.BuildProblem(samples, &trial);
    const ceres::Solver::Summary summary =
        fitter.Solve(problem.get(), std::min(options.start_iterations, options.max_iterations));
    *iterations += static_cast<int>(summary.iterations.size());
    if (std::isfinite(summary.final_cost) && summary.final_cost < best_cost) {
      best_cost = summary.final_cost;
      best = trial;
    }
  }
  if (!std::isfinite(best_cost)) throw ComputeError("every start of the fit failed");
  return best;
}

}  // namespace brdf::fitters
