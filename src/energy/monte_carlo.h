// Monte Carlo albedo estimates: draw wi from a mixture of power-cosine densities (one
// strategy, the cosine-weighted hemisphere, is plain cosine sampling; adding the model's lobes
// is importance sampling), average f cos(theta_i) / pdf, and report one standard error.
#pragma once

#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "energy/integrand.h"

namespace brdf {

// One density of the mixture: a power-cosine lobe in the given frame, chosen with probability
// `weight` (weights are normalised to sum to one).
struct SamplingStrategy {
  LobeCoordinates coordinates;
  double weight = 1.0;
};

// Draws a direction from one strategy given wo, and the strategy's pdf (solid angle) of a wi.
// Half-vector strategies draw h and reflect wo about it; wi may fall below the horizon.
Vec3 SampleStrategy(const LobeCoordinates& coordinates, const Vec3& wo, const Point2& u);
double StrategyPdf(const LobeCoordinates& coordinates, const Vec3& wo, const Vec3& wi);

// The mixture estimator of ∫ f cos dwi with `samples` draws (Veach & Guibas 1995: one-sample
// model with the balance heuristic, i.e. dividing by the mixture pdf). Deterministic for a
// given stream.
AlbedoEstimate EstimateAlbedoByMixture(const BrdfFunction& brdf, const Vec3& wo,
                                       const std::vector<SamplingStrategy>& strategies,
                                       int64_t samples, Rng* stream);

// Cosine-weighted sampling alone: the estimator is pi f(wi, wo).
AlbedoEstimate EstimateAlbedoCosine(const BrdfFunction& brdf, const Vec3& wo, int64_t samples,
                                    Rng* stream);

}  // namespace brdf
