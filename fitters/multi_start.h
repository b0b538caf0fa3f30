// The multi-start (DESIGN §6): local minima are real — a lobe started too broad or too sharp
// settles on the diffuse floor or on one bright sample, and a microfacet lobe started with a
// metal's f0 can mistake a grazing Fresnel rise for a sharp peak. Every start of
// ModelFitter::Starts() is solved on a small subsample (each start only has to find its basin,
// not its optimum); the lowest cost wins. The starts are screened first: every start gets a few
// iterations on a smaller subsample still, the lowest quarter as many more on the whole start
// subsample, and only the lowest few of those continue to the full count. A two-lobe composition
// has the product of its lobes' starts (196 for lambert+ggx+ggx); the screen spends most of the
// time on the starts still in the running.
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "core/errors.h"
#include "fitters/model_fitter.h"
#include "fitters/solve.h"

namespace brdf::fitters {

namespace multi_start_detail {
// Iterations every start gets in the screen, on how many samples (a stratified subsample of the
// start subsample); how many starts continue for as many iterations on every start sample (at
// least kSecondRoundStarts, else the lowest quarter), and how many of those to the full count
// (at least kKeptStarts, else the lowest sixteenth). A single lobe's starts (at most
// kMaxUnscreened, with the low-floor copies of a designed schedule) are never screened:
// screening them, keeping 4 to 8 of 14, missed the exhaustive search's optimum by 2-3 % on two
// bundled files (krylon_blue blinn-phong, retro-3M-jaune phong) or moved the pinned ggx and
// beckmann fits of cayman and mystique by up to 0.9 %. On the 16 MERL tables of the lbfit
// comparison, screens of 3 iterations on 500 to 4000 samples keeping 12 starts give `auto` the
// same image error on every table (docs/fitting.md). With one screening round, which kept the
// lowest 12 after 3 iterations on 1000 samples, the two-lobe fit of retro-gray-tape missed the
// exhaustive search's optimum by 5 % for two of eight subsample seeds; the second round finds it
// within 0.4 % for all eight (docs/fitting.md).
inline constexpr int kScreenIterations = 3;
inline constexpr size_t kScreenSamples = 1000;
inline constexpr size_t kSecondRoundStarts = 48;
inline constexpr size_t kKeptStarts = 12;
inline constexpr size_t kMaxUnscreened = 28;
}  // namespace multi_start_detail

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
  const int total = std::min(options.start_iterations, options.max_iterations);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const bool screened = starts.size() > multi_start_detail::kMaxUnscreened;
  const int screen = screened ? std::min(total, multi_start_detail::kScreenIterations) : total;
  // Subsample keeps every sample of a set no larger than kScreenSamples.
  const std::vector<FitSample> screen_samples =
      screened ? Subsample(samples, multi_start_detail::kScreenSamples, options.seed + 2)
               : std::vector<FitSample>();
  std::optional<FitObjective<ModelType>> screen_objective;
  if (screened) {
    screen_objective.emplace(screen_samples, options.loss, options.grey_specular,
                             options.samples_per_block);
  }
  // The starts are independent: solved side by side (each on Ceres' one thread, its batches in
  // parallel), then compared in their order, so the choice does not depend on the thread count.
  std::vector<std::vector<double>> trials(starts.size());
  std::vector<double> costs(starts.size());
  std::vector<int> start_iterations(starts.size());
  const auto solve = [&](const FitObjective<ModelType>& on, size_t k, int budget) {
    const ceres::Solver::Summary summary =
        SolveLeastSquares(on, &trials[k], fitter.lower(), fitter.upper(), budget);
    start_iterations[k] += static_cast<int>(summary.iterations.size());
    costs[k] = std::isfinite(summary.final_cost) ? summary.final_cost : kInfinity;
  };
  tbb::parallel_for(size_t{0}, starts.size(), [&](size_t k) {
    trials[k] = fitter.InitialGuess(samples, starts[k]);
    solve(screened ? *screen_objective : objective, k, screen);
  });
  // The screen, in two rounds (successive halving): the lowest quarter of the screen's costs
  // continue for as many iterations on all the start samples, and the lowest of those continue
  // to the full count (ties in start order, so the set does not depend on the thread count).
  const auto keep_lowest = [&](size_t count) {
    std::vector<size_t> order(starts.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return costs[a] < costs[b]; });
    for (size_t j = std::min(count, order.size()); j < order.size(); ++j) {
      costs[order[j]] = kInfinity;
    }
    order.resize(std::min(count, order.size()));
    return order;
  };
  const int second_round = std::min(screen, total - screen);
  if (screened && second_round > 0) {
    const std::vector<size_t> second =
        keep_lowest(std::max(multi_start_detail::kSecondRoundStarts, starts.size() / 4));
    tbb::parallel_for(size_t{0}, second.size(), [&](size_t j) {
      if (std::isfinite(costs[second[j]])) solve(objective, second[j], second_round);
    });
  }
  if (screened && total > screen + second_round) {
    const std::vector<size_t> kept =
        keep_lowest(std::max(multi_start_detail::kKeptStarts, starts.size() / 16));
    tbb::parallel_for(size_t{0}, kept.size(), [&](size_t j) {
      if (std::isfinite(costs[kept[j]])) solve(objective, kept[j], total - screen - second_round);
    });
  }
  std::vector<double> best;
  double best_cost = kInfinity;
  for (size_t k = 0; k < starts.size(); ++k) {
    *iterations += start_iterations[k];
    if (costs[k] < best_cost) {
      best_cost = costs[k];
      best = trials[k];
    }
  }
  if (!std::isfinite(best_cost)) throw ComputeError("every start of the fit failed");
  return best;
}

}  // namespace brdf::fitters
