// The preview's lobe technique (render/sphere.h) in single precision: the densities of
// SampleStrategy / StrategyPdf (energy/monte_carlo.h) for one pixel's wo.
//
// The power cosine, (e+1)/(2 pi) cos^e(beta) about the lobe frame's axis in wi (the normal,
// the mirror direction, ...) or (in the half vector) about the normal, is written here in float.
// Its warp and density carry 1 - cos(beta) instead of cos(beta): near the axis of a sharp lobe (e =
// 1e4: beta ~ 0.5 deg) the cosine differs from 1 in its fifth digit, and a float cosine would keep
// one or two digits of what the density depends on. 1 - cos(beta) comes from differences of unit
// vectors (|a - b|^2 / 2, or sin^2 / (1 + cos) of the half vector), which keep their digits. A lobe
// with its own distribution (the microfacet models' normals, models/lobe.h) is drawn and evaluated
// by its own float functions where it has them (ggx), else by energy/monte_carlo.cpp in double.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/float_math.h"
#include "core/simd.h"
#include "energy/monte_carlo.h"
#include "models/lobe.h"

namespace brdf {

// What the lobe technique keeps of a lobe for a whole render.
//
// Its core: the cone about the lobe's axis (in wi, or in the half vector) outside which the
// lobe's density falls below kCoreDensity, a thousandth of the cosine technique's peak. The
// multiple importance sampling weights count the lobe's pdf as zero outside the core (MisPdf),
// for every technique alike: the weights still sum to one at every direction and each
// technique still divides by its own true pdf, so the estimate stays unbiased (Veach 1997,
// §9.2: any weights that sum to one will do), while the light and cosine samples, most of
// which fall far from a narrow lobe, skip its exponential.
//
// A lobe with its own distribution (the microfacet normals, evaluated through the
// distribution's function pointers) enters the weights through a cache-sized table instead: its
// density of the half vector, D(h) cos(theta_h), at 4096 points uniform in sqrt(1 - cos theta_h),
// interpolated linearly. For the same reason as the core the weights need not be exact, only
// the same for every technique; the lobe's own sample still divides by its exact pdf.
struct LobeTechnique {
  static constexpr double kCoreDensity = 1e-3 * kInvPi;
  static constexpr int kTableSize = 4096;

  explicit LobeTechnique(const LobeCoordinates& lobe);
  // The tabulated density of the half vector at 1 - cos(theta_h) (distributions only).
  float TabulatedDensity(float one_minus_cos) const {
    const float position = std::sqrt(std::max(0.0f, one_minus_cos)) * (kTableSize - 1);
    const int below = std::min(static_cast<int>(position), kTableSize - 2);
    const float t = std::min(position - static_cast<float>(below), 1.0f);
    return (1.0f - t) * density_table[below] + t * density_table[below + 1];
  }

  LobeCoordinates lobe;
  float core_one_minus_cos = 2.0f;  // 1 - cos(beta) at the core's rim (2: everywhere)
  std::vector<float> density_table;
};

class LobeSampler {
 public:
  // For the outgoing direction `wo` (unit, local frame); keeps a reference to `technique`,
  // which must outlive the sampler.
  LobeSampler(const LobeTechnique& technique, const Vec3f& wo);
  LobeSampler(LobeTechnique&& technique, const Vec3f& wo) = delete;

  // wi from u in [0, 1)^2; it may lie below the horizon (a half-vector lobe reflects wo).
  Vec3f Sample(float u0, float u1) const;
  // The density of wi in solid angle.
  float Pdf(const Vec3f& wi) const;
  // The same for a wi whose MisPdf is mis_pdf > 0 (inside the core): a power cosine's MisPdf
  // is its Pdf there, so only a distribution of its own evaluates again.
  float PdfInCore(const Vec3f& wi, float mis_pdf) const {
    return lobe_.distribution == nullptr ? mis_pdf : Pdf(wi);
  }
  // The lobe's pdf as the weights count it: 0 outside the core; inside, Pdf (a power
  // cosine) or the tabulated density (a distribution of its own).
  float MisPdf(const Vec3f& wi) const;

  // Sample and MisPdf for `count` samples (directions one array per coordinate). A power
  // cosine's run in loops that vectorize (the same numbers as one at a time).
  void SampleBatch(const float* u0, const float* u1, int count, float* x, float* y, float* z) const;
  void MisPdfBatch(const float* x, const float* y, const float* z, int count, float* mis_pdf) const;

  // The largest density of wi the lobe reaches (at its axis, seen from the normal), per sr.
  static double PeakDensity(const LobeCoordinates& lobe);

 private:
  // 1 - cos of the angle between the lobe's axis and wi (or its half vector with wo); 2 where
  // there is none.
  float AxisOneMinusCos(const Vec3f& wi) const;
  // One sample of a power cosine in the lobe's frame, inline and without branches for the
  // batch loops (lobe_sampler.cpp): for wi = (x, y, z), AxisOneMinusCos in *one_minus_cos and
  // the factor from the density of the axis variable to that of wi (the half-vector
  // Jacobian; 1 in wi's own frames; 0 where wi has none); and the draw from (u0, u1).
  template <bool kHalfVector>
  float PowerCosineAxis(float x, float y, float z, float* one_minus_cos) const;
  template <bool kHalfVector>
  void PowerCosineSample(float u0, float u1, float* x, float* y, float* z) const;
  template <bool kHalfVector>
  void PowerCosineSamples(const float* u0, const float* u1, int count, float* x, float* y,
                          float* z) const;
  // MisPdfBatch in the lobe's frame (a distribution's: the half vector).
  template <bool kHalfVector>
  void AxisMisPdfs(const float* x, const float* y, const float* z, int count, float* mis_pdf) const;
  // Every lobe's MisPdf a batch at a time, through the templates of the lobe's frame; compiled
  // a second time for AVX2 (8 lanes; no FMA, so the same float operations and numbers as the
  // baseline's 4) and chosen at run time. (The power cosine's draws stay 4 lanes wide: GCC 12
  // compiles their loop scalar for AVX2.)
  BRDF_AVX2 void MisPdfsAvx2(const float* x, const float* y, const float* z, int count,
                             float* mis_pdf) const;
  void MisPdfsIn(const float* x, const float* y, const float* z, int count, float* mis_pdf) const;
  // (e+1)/(2 pi) (1 - one_minus_cos)^e, keeping the digits of a cosine near 1.
  BRDF_LANE_FUNCTION float PowerCosineDensity(float one_minus_cos) const {
    const float density =
        normalization_ * ExpNonPositive(exponent_ * LogOneMinus(std::min(one_minus_cos, 1.0f)));
    return one_minus_cos < 1.0f ? density : 0.0f;
  }

  const LobeTechnique& technique_;
  LobeCoordinates lobe_;
  float core_one_minus_cos_;
  // For a distribution: wi's pdf is density(h) times this (visible normals: G1(wo) /
  // (4 cos theta_o cos theta_h), as D_wo(h) = G1(wo) (wo.h) D(h) / cos theta_o; else
  // 1 / (4 wo.h)), without the cos theta_h or wo.h factor, which MisPdf applies.
  float visible_scale_ = 0.0f;
  bool visible_normals_ = false;  // a distribution drawing the normals visible from wo
  Vec3f wo_;
  Vec3 wo_double_;
  float exponent_ = 1.0f, normalization_ = 1.0f, inverse_exponent_plus_one_ = 0.5f;
  // About an axis in wi: the tangent frame about it (rows; the last is the axis).
  Eigen::Matrix3f axis_frame_ = Eigen::Matrix3f::Identity();
  bool avx2_ = Avx2Enabled();
};

}  // namespace brdf
