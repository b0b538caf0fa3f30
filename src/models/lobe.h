// Where a model's lobe lies and how its mass is spread, for every integrator that needs to find
// it: the albedo quadrature warps its polar angle by the lobe's CDF, the importance samplers of
// `brdf energy` and of the preview renderer draw from it (DESIGN §7, §8). A model states its
// own lobe (Model::Lobe in each header); nothing else knows the model list.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/sampling.h"
#include "core/vec.h"

namespace brdf {

// Where a lobe is centred: about the normal in the half vector h, wi = Reflect(wo, h) (Blinn,
// microfacets), or about an axis in wi that follows wo: `axis(wo)`, a unit vector above the
// horizon for every unit wo above it (the mirror direction of wo for phong, wo itself for a
// back-scattering lobe), or the normal when it is null (a diffuse term, or no known lobe). A
// model term states its own frame, so a lobe about a new axis is a change to that term's file
// alone: the integrators and samplers ask the frame, never which one it is.
struct LobeFrame {
  bool half_vector = false;
  Vec3 (*axis)(const Vec3& wo) = nullptr;
  // How a diagnostic names the angle from the lobe's centre.
  const char* offset_name = "angle from the normal";

  // Whether the lobe lies about the fixed normal (the cosine's own axis).
  constexpr bool AboutNormal() const { return !half_vector && axis == nullptr; }
  // The axis in wi of a lobe about an axis (not a half-vector lobe).
  Vec3 Axis(const Vec3& wo) const { return axis != nullptr ? axis(wo) : Vec3::UnitZ(); }
};

inline constexpr LobeFrame kNormalFrame{};
inline constexpr LobeFrame kHalfVectorFrame{true, nullptr, "half-vector angle"};

// A rotationally symmetric density p(beta) in solid angle about the lobe's axis, given by three
// functions of the polar angle beta and the lobe's shape parameter:
//   mass_beyond(cos beta) = ∫ over beta' > beta of p dω, 1 at the axis and 0 at 90 deg,
//   cos_at(u) its inverse (the warp: u uniform in (0, 1] spreads the lobe's mass evenly),
//   density(cos beta) = p.
// The power cosine (e+1)/(2π) cos^e is the default; a microfacet model supplies D(h) cos(theta_h),
// whose integral over the hemisphere is 1 (the normal distribution's own normalization).
//
// A half-vector distribution may also sample the normals visible from wo (wo-dependent, so
// the samplers use it but the quadrature's warp does not): sample_visible draws h from
// u in [0, 1)^2, visible_density is that density of h in solid angle. Both null: the samplers
// draw h from `density`.
struct LobeDistribution {
  const char* name;
  double (*mass_beyond)(double cos_beta, double shape);
  double (*cos_at)(double u, double shape);
  double (*density)(double cos_beta, double shape);
  Vec3 (*sample_visible)(const Vec3& wo, double u0, double u1, double shape) = nullptr;
  double (*visible_density)(const Vec3& wo, const Vec3& h, double shape) = nullptr;
  // `density` and `sample_visible` in single precision, for the preview renderer's hot loop
  // (render/lobe_sampler.h); null: it calls the double ones. Only the density of h is needed:
  // the visible normals' density of wi is D(h) times a factor of wo alone, G1(wo) / (4 cos
  // theta_o), which the renderer takes once a pixel. The draw takes `count` pairs (u0[k],
  // u1[k]) for one wo and writes h = (x[k], y[k], z[k]).
  float (*density_float)(float cos_beta, float shape) = nullptr;
  void (*sample_visible_float)(const Vec3T<float>& wo, const float* u0, const float* u1, int count,
                               float* x, float* y, float* z, float shape) = nullptr;
};

// A lobe frame and its density (the power cosine of core/sampling.h unless a distribution is
// given). `exponent` is the power-cosine exponent e (also the shape
// parameter handed to a non-default distribution's functions, e.g. a microfacet alpha).
struct LobeCoordinates {
  LobeFrame frame = kNormalFrame;
  double exponent = 1.0;
  const LobeDistribution* distribution = nullptr;  // nullptr: the power cosine
  // Panels of the quadrature's azimuthal rule on each ring about the axis: 1 for a lobe that is
  // rotationally symmetric about it (constant on every ring); more for one that is not, whose
  // value varies along a ring as fast as its widths differ (ggx-aniso).
  int ring_panels = 1;
};

// The lobe's warp, its inverse and its density, whatever the distribution.
inline double LobeCosAt(const LobeCoordinates& lobe, double u) {
  if (lobe.distribution == nullptr) return PowerCosineLobeCosTheta(u, lobe.exponent);
  return lobe.distribution->cos_at(u, lobe.exponent);
}
inline double LobeMassBeyond(const LobeCoordinates& lobe, double cos_beta) {
  if (lobe.distribution == nullptr) {
    return std::pow(std::max(0.0, cos_beta), lobe.exponent + 1.0);
  }
  return lobe.distribution->mass_beyond(std::max(0.0, cos_beta), lobe.exponent);
}
inline double LobeDensity(const LobeCoordinates& lobe, double cos_beta) {
  if (lobe.distribution == nullptr) return PowerCosineLobePdf(cos_beta, lobe.exponent);
  if (cos_beta <= 0.0) return 0.0;
  return lobe.distribution->density(cos_beta, lobe.exponent);
}

}  // namespace brdf
