// The pieces of the renderers' reflectance models that differ from ours (src/models/), written
// for our own code so that an exported material can be evaluated and compared with the fit it
// came from. Each formula names the renderer source or specification it follows.
//
// Ours (DESIGN §2): f = rho_d/π + F_Schlick(wi·h) D(h) G2(wi, wo) / (4 cos theta_i cos theta_o)
// with the height-correlated Smith G2 = 1 / (1 + Λ(wi) + Λ(wo)) (Heitz 2014, eq. 99).
#pragma once

#include <cmath>

#include "core/vec.h"
#include "models/beckmann.h"
#include "models/ggx.h"
#include "models/microfacet.h"

namespace brdf::exporters {

enum class Distribution { kGgx, kBeckmann };

// How a renderer couples masking and shadowing.
enum class Masking {
  // 1 / (1 + Λ(wi) + Λ(wo)): ours and pbrt-v4's TrowbridgeReitzDistribution::G.
  kHeightCorrelated,
  // G1(wi) G1(wo) with G1 = 1 / (1 + Λ): glTF 2.0 Appendix B (V_GGX), Mitsuba 3's
  // MicrofacetDistribution::G for GGX.
  kSeparable,
  // G1(wi) G1(wo) with Walter et al.'s rational fit of the Beckmann G1 (EGSR 2007, eq. 27;
  // "< 0.35 % relative error"), which Mitsuba 3 evaluates for its Beckmann distribution.
  kSeparableRational,
};

inline double NormalDistribution(Distribution distribution, double cos_theta_h, double alpha) {
  return distribution == Distribution::kGgx ? models::GgxLobe::D<double>(cos_theta_h, alpha)
                                            : models::BeckmannLobe::D<double>(cos_theta_h, alpha);
}

inline double SmithLambda(Distribution distribution, double cos_theta, double alpha) {
  return distribution == Distribution::kGgx
             ? models::GgxLobe::Lambda<double>(cos_theta, alpha)
             : models::BeckmannLobe::Lambda<double>(cos_theta, alpha);
}

// Walter et al. 2007, eq. 27, with a = 1 / (alpha tan theta): 1 for a >= 1.6.
inline double BeckmannG1Rational(double cos_theta, double alpha) {
  const double tan2 = models::TanSquared(cos_theta);
  if (!(tan2 > 0.0)) return 1.0;
  const double a = 1.0 / (alpha * std::sqrt(tan2));
  if (a >= 1.6) return 1.0;
  return (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}

inline double MaskingShadowing(Masking masking, Distribution distribution, double cos_theta_i,
                               double cos_theta_o, double alpha) {
  switch (masking) {
    case Masking::kHeightCorrelated:
      return 1.0 / (1.0 + SmithLambda(distribution, cos_theta_i, alpha) +
                    SmithLambda(distribution, cos_theta_o, alpha));
    case Masking::kSeparable:
      return 1.0 / ((1.0 + SmithLambda(distribution, cos_theta_i, alpha)) *
                    (1.0 + SmithLambda(distribution, cos_theta_o, alpha)));
    case Masking::kSeparableRational:
      return BeckmannG1Rational(cos_theta_i, alpha) * BeckmannG1Rational(cos_theta_o, alpha);
  }
  return 0.0;
}

// The geometry of one (wi, wo) pair that every microfacet term reads.
struct HalfVectorGeometry {
  double cos_theta_i = 0, cos_theta_o = 0, cos_theta_h = 0, cos_theta_d = 0;
  bool above = false;  // both directions strictly above the surface
};
inline HalfVectorGeometry Geometry(const Vec3& wi, const Vec3& wo) {
  HalfVectorGeometry g;
  g.cos_theta_i = wi.z();
  g.cos_theta_o = wo.z();
  g.above = g.cos_theta_i > 0.0 && g.cos_theta_o > 0.0;
  if (!g.above) return g;
  const Vec3 half_vector = (wi + wo).normalized();
  g.cos_theta_h = half_vector.z();
  g.cos_theta_d = wi.dot(half_vector);
  return g;
}

// A microfacet specular lobe without its Fresnel factor: D G / (4 cos theta_i cos theta_o).
struct MicrofacetLobe {
  Distribution distribution = Distribution::kGgx;
  Masking masking = Masking::kHeightCorrelated;
  double alpha = 0.1;

  double D(const HalfVectorGeometry& g) const {
    return NormalDistribution(distribution, g.cos_theta_h, alpha);
  }
  double G(const HalfVectorGeometry& g) const {
    return MaskingShadowing(masking, distribution, g.cos_theta_i, g.cos_theta_o, alpha);
  }
  double Eval(const HalfVectorGeometry& g) const {
    if (!g.above) return 0.0;
    return D(g) * G(g) / (4.0 * g.cos_theta_i * g.cos_theta_o);
  }
};

// Exact reflectance of a conductor of relative index eta + i k, per channel: pbrt-v4's
// FrComplex and Mitsuba 3's fresnel_conductor compute this (Born & Wolf §14.2), the same
// function the virtual gonioreflectometer's facets use (models/microfacet.h).
inline Rgb ConductorFresnel(double cos_theta_d, const Rgb& eta, const Rgb& k) {
  Rgb f;
  for (int c = 0; c < 3; ++c) f[c] = models::FresnelReflectance(cos_theta_d, eta[c], k[c]);
  return f;
}

// The extinction k that gives a conductor of eta = 1 the normal-incidence reflectance r:
// R(0) = k² / (4 + k²) = r. pbrt-v4 maps a conductor's "reflectance" so (ConductorMaterial);
// at grazing incidence the reflectance rises to 1, as Schlick's does.
inline double ExtinctionForReflectance(double r) {
  const double clamped = std::min(std::max(r, 0.0), 0.9999);
  return 2.0 * std::sqrt(clamped) / std::sqrt(1.0 - clamped);
}

}  // namespace brdf::exporters
