// What the albedo integrators integrate and what they return. An integrand is a BRDF for a
// fixed outgoing direction; the directional albedo is a(wo) = ∫_H f(wi, wo) cos(theta_i) dwi
// (DESIGN §1). A model splits into terms, each integrated in the coordinates that suit its lobe.
#pragma once

#include <cstdint>
#include <functional>

#include "core/vec.h"
#include "models/lobe.h"

namespace brdf {

// One BRDF value (sr^-1, no cosine factor). `supported` is false where measured data has a hole
// there (a missing MERL cell, or no sample near enough); the integrators report the
// cosine-weighted share of such directions as lost coverage. A non-finite value counts as
// unsupported and contributes zero.
struct BrdfSample {
  Rgb value = Rgb::Zero();
  bool supported = true;
};
using BrdfFunction = std::function<BrdfSample(const Vec3& wi, const Vec3& wo)>;

// LobeFrame and LobeCoordinates (where a term's lobe lies and how its mass is spread) come with
// the models: models/lobe.h.

// A directional albedo with its error estimate, per channel.
struct AlbedoEstimate {
  Rgb albedo = Rgb::Zero();
  // Quadrature: the estimated absolute error (Kronrod minus Gauss, summed). Monte Carlo: one
  // standard error of the mean.
  Rgb error = Rgb::Zero();
  // Share of the cosine-weighted hemisphere (∫ cos dω = π) where the data support the value.
  double coverage = 1.0;
  int64_t evaluations = 0;  // BRDF evaluations spent

  // Sum of independent terms: albedos and errors add, coverage is the smallest.
  AlbedoEstimate& operator+=(const AlbedoEstimate& other);
};

}  // namespace brdf
