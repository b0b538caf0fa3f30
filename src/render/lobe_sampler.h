// The preview's lobe technique (render/sphere.h) in single precision: the densities of
// SampleStrategy / StrategyPdf (energy/monte_carlo.h) for one pixel's wo.
//
// The power cosine, (e+1)/(2 pi) cos^e(beta) about the normal, the mirror direction or (in the
// half vector) the normal, is written here in float. Its warp and density carry 1 - cos(beta)
// instead of cos(beta): near the axis of a sharp lobe (e = 1e4: beta ~ 0.5 deg) the cosine
// differs from 1 in its fifth digit, and a float cosine would keep one or two digits of what
// the density depends on. 1 - cos(beta) comes from sines (|a - b|^2 / 2 between unit vectors,
// or sin^2 / (1 + cos) about the normal), which keep their digits. A lobe with its own
// distribution (the microfacet models' normals, models/lobe.h) is drawn and evaluated by
// energy/monte_carlo.cpp in double.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "energy/monte_carlo.h"
#include "models/lobe.h"
#include "render/float_math.h"

namespace brdf {

class LobeSampler {
 public:
  // For the outgoing direction `wo` (unit, local frame).
  LobeSampler(const LobeCoordinates& lobe, const Vec3f& wo);

  // wi from u in [0, 1)^2; it may lie below the horizon (a half-vector lobe reflects wo).
  Vec3f Sample(float u0, float u1) const;
  // The density of wi in solid angle.
  float Pdf(const Vec3f& wi) const;

  // The largest density of wi the lobe reaches (at its axis, seen from the normal), per sr.
  static double PeakDensity(const LobeCoordinates& lobe);

 private:
  // (e+1)/(2 pi) (1 - one_minus_cos)^e, keeping the digits of a cosine near 1.
  float PowerCosineDensity(float one_minus_cos) const {
    if (!(one_minus_cos < 1.0f)) return 0.0f;
    return normalization_ * std::exp(exponent_ * LogOneMinus(one_minus_cos));
  }
  // A direction about +z of the lobe's frame: 1 - cos(beta) = 1 - u^(1/(e+1)), likewise.
  Vec3f SampleAboutAxis(float u0, float u1) const;

  LobeCoordinates lobe_;
  Vec3f wo_;
  Vec3 wo_double_;
  float exponent_ = 1.0f, normalization_ = 1.0f, inverse_exponent_plus_one_ = 0.5f;
  Eigen::Matrix3f mirror_frame_;  // rows: the tangent frame about the mirror direction of wo
};

}  // namespace brdf
