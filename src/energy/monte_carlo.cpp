#include "energy/monte_carlo.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "core/sampling.h"

namespace brdf {
namespace {

// A direction about +z drawn from the lobe's density (models/lobe.h): the polar angle by
// inverting the lobe's mass beyond it, the azimuth uniform.
Vec3 SampleLobeAboutZ(const LobeCoordinates& lobe, const Point2& u) {
  if (lobe.distribution == nullptr) return SamplePowerCosineLobe(u, lobe.exponent);
  // 1 - u: u in [0, 1) maps to a mass in (0, 1], never exactly the horizon.
  const double cos_theta = LobeCosAt(lobe, 1.0 - u.x());
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * u.y();
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

// Whether the lobe draws the half vector from the normals visible from wo (models/lobe.h);
// only for wo above the surface, where they are defined.
bool VisibleNormals(const LobeCoordinates& lobe, const Vec3& wo) {
  return lobe.distribution != nullptr && lobe.distribution->sample_visible != nullptr &&
         wo.z() > 0.0;
}

}  // namespace

Vec3 SampleStrategy(const LobeCoordinates& coordinates, const Vec3& wo, const Point2& u) {
  const LobeFrame& frame = coordinates.frame;
  if (frame.half_vector) {
    if (VisibleNormals(coordinates, wo)) {
      return Reflect(
          wo, coordinates.distribution->sample_visible(wo, u.x(), u.y(), coordinates.exponent));
    }
    return Reflect(wo, SampleLobeAboutZ(coordinates, u));
  }
  if (frame.AboutNormal()) {
    return coordinates.exponent == 1.0 ? SampleCosineHemisphere(u)
                                       : SamplePowerCosineLobe(u, coordinates.exponent);
  }
  return Frame::FromZ(frame.Axis(wo)).FromLocal(SamplePowerCosineLobe(u, coordinates.exponent));
}

double StrategyPdf(const LobeCoordinates& coordinates, const Vec3& wo, const Vec3& wi) {
  const LobeFrame& frame = coordinates.frame;
  if (frame.half_vector) {
    const Vec3 sum = wi + wo;
    if (sum.squaredNorm() <= 0.0) return 0.0;
    const Vec3 half_vector = sum.normalized();
    const double density =
        VisibleNormals(coordinates, wo)
            ? coordinates.distribution->visible_density(wo, half_vector, coordinates.exponent)
            : LobeDensity(coordinates, CosTheta(half_vector));
    return HalfVectorToIncidentPdf(density, wo.dot(half_vector));
  }
  if (frame.AboutNormal()) {
    return coordinates.exponent == 1.0 ? CosineHemispherePdf(CosTheta(wi))
                                       : PowerCosineLobePdf(CosTheta(wi), coordinates.exponent);
  }
  return PowerCosineLobePdf(wi.dot(frame.Axis(wo)), coordinates.exponent);
}

AlbedoEstimate EstimateAlbedoByMixture(const BrdfFunction& brdf, const Vec3& wo,
                                       const std::vector<SamplingStrategy>& strategies,
                                       int64_t samples, Rng* stream) {
  if (samples < 2) throw UsageError("Monte Carlo needs at least 2 samples");
  double total_weight = 0;
  for (const SamplingStrategy& strategy : strategies) total_weight += strategy.weight;
  if (strategies.empty() || !(total_weight > 0.0)) {
    throw UsageError("importance sampling needs a strategy with positive weight");
  }
  // Welford's running mean and sum of squared deviations, per channel: stable for 1e8 samples.
  Rgb mean = Rgb::Zero(), squared_deviations = Rgb::Zero();
  double unsupported = 0;  // sum of cos/pdf over draws in holes: estimates their cosine measure
  for (int64_t k = 0; k < samples; ++k) {
    // Choose a strategy with the first number, then draw its direction with the next two.
    double choice = stream->Uniform() * total_weight;
    size_t chosen = 0;
    while (chosen + 1 < strategies.size() && choice >= strategies[chosen].weight) {
      choice -= strategies[chosen].weight;
      ++chosen;
    }
    const Vec3 wi = SampleStrategy(strategies[chosen].coordinates, wo, stream->Uniform2D());
    Rgb value = Rgb::Zero();
    if (CosTheta(wi) > 0.0) {
      double pdf = 0;
      for (const SamplingStrategy& strategy : strategies) {
        pdf += strategy.weight / total_weight * StrategyPdf(strategy.coordinates, wo, wi);
      }
      const BrdfSample sample = brdf(wi, wo);
      const bool finite = sample.value.allFinite();
      if (pdf > 0.0 && (!sample.supported || !finite)) unsupported += CosTheta(wi) / pdf;
      if (pdf > 0.0 && finite) value = sample.value * (CosTheta(wi) / pdf);
    }
    const Rgb delta = value - mean;
    mean += delta / static_cast<double>(k + 1);
    squared_deviations += delta * (value - mean);
  }
  AlbedoEstimate estimate;
  estimate.albedo = mean;
  estimate.error =
      (squared_deviations / static_cast<double>(samples - 1) / static_cast<double>(samples)).sqrt();
  estimate.coverage =
      std::clamp(1.0 - unsupported / static_cast<double>(samples) * kInvPi, 0.0, 1.0);
  estimate.evaluations = samples;
  return estimate;
}

AlbedoEstimate EstimateAlbedoCosine(const BrdfFunction& brdf, const Vec3& wo, int64_t samples,
                                    Rng* stream) {
  return EstimateAlbedoByMixture(brdf, wo, {{{kNormalFrame, 1.0}, 1.0}}, samples, stream);
}

}  // namespace brdf
