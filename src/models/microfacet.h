// What the microfacet models of DESIGN §2 share: Fresnel (Schlick's approximation, and the
// exact reflectance of a smooth interface that the virtual gonioreflectometer's facets use),
// the height-correlated Smith masking-shadowing term, and the model template itself:
//
//   f(wi, wo) = rho_d/π + F(wi·h) D(h) G2(wi, wo) / (4 cos theta_i cos theta_o)
//
// with h = normalize(wi + wo). A model (ggx.h, beckmann.h) supplies its normal distribution D,
// its Smith Λ, its name and the density the samplers draw half vectors from. Everything is
// templated on the scalar so that one definition serves double and ceres::Jet (STYLE rule 3).
//
// Parameters: rho_d (RGB, default 0.5), f0 (RGB, Fresnel reflectance at normal incidence in
// [0, 1], default 0.04, a dielectric of index 1.5), alpha (roughness, not squared, default 0.1).
#pragma once

#include <cmath>

#include "models/common.h"

namespace brdf::models {

// Schlick, "An inexpensive BRDF model for physically-based rendering", CGF 13(3), 1994:
// F = f0 + (1 - f0)(1 - cos theta_d)^5, per channel. Linear in f0, which the fitter's energy
// bound uses (fitters/microfacet_bound.h).
template <typename D, typename T>
T SchlickFresnel(const D& cos_theta_d, const T& f0) {
  const D m = cos_theta_d >= D(1) ? D(0) : (cos_theta_d <= D(0) ? D(1) : D(1) - cos_theta_d);
  const D m2 = m * m;
  return f0 + (T(1) - f0) * (m2 * m2 * m);
}

// Exact Fresnel reflectance of a smooth interface from air for unpolarized light, with the
// relative index n + i k (k = 0: a dielectric). Written in real arithmetic (Born & Wolf,
// Principles of Optics, §14.2; the form given by Cook & Torrance 1982 for metals): with
//   a² + b² = sqrt((n² − k² − sin²θ)² + 4 n² k²),   a² = (a² + b² + n² − k² − sin²θ) / 2,
//   R_s = (a² + b² − 2a cos θ + cos²θ) / (a² + b² + 2a cos θ + cos²θ),
//   R_p = R_s ((a² + b²) cos²θ − 2a cos θ sin²θ + sin⁴θ) / ((a² + b²) cos²θ + 2a cos θ sin²θ +
//   sin⁴θ),
// R = (R_s + R_p) / 2. Equal to |r_s|² and |r_p|² of the complex Fresnel amplitudes (the
// surface tests check it against that form); real arithmetic avoids complex sqrt and division
// in the tracer's inner loop.
template <typename T>
T FresnelReflectance(T cos_theta, const T& n, const T& k) {
  using std::sqrt;
  if (cos_theta < T(0)) cos_theta = T(0);
  if (cos_theta > T(1)) cos_theta = T(1);
  const T cos2 = cos_theta * cos_theta, sin2 = T(1) - cos2;
  const T t0 = n * n - k * k - sin2;
  const T a2_plus_b2 = sqrt(t0 * t0 + T(4) * n * n * k * k);
  const T a_squared = T(0.5) * (a2_plus_b2 + t0);
  const T a = a_squared > T(0) ? sqrt(a_squared) : T(0);
  const T r_s_num = a2_plus_b2 - T(2) * a * cos_theta + cos2;
  const T r_s_den = a2_plus_b2 + T(2) * a * cos_theta + cos2;
  const T r_s = r_s_den > T(0) ? r_s_num / r_s_den : T(1);
  const T t1 = a2_plus_b2 * cos2 + sin2 * sin2, t2 = T(2) * a * cos_theta * sin2;
  const T r_p = t1 + t2 > T(0) ? r_s * (t1 - t2) / (t1 + t2) : T(1);
  return T(0.5) * (r_s + r_p);
}

// tan²(theta) of a direction from its cosine; 0 at the normal.
template <typename D>
D TanSquared(const D& cos_theta) {
  const D cos2 = cos_theta * cos_theta;
  return (D(1) - cos2) / cos2;
}

// The model template. `Model` (the derived struct, CRTP) provides
//   template <T, D> static T D(const D& cos_theta_h, const T& alpha);    normal distribution
//   template <T, D> static T Lambda(const D& cos_theta, const T& alpha); Smith Λ
//   static const LobeDistribution kLobeDistribution;                      D(h) cos(theta_h)
//   static double AlphaEquivalentExponent(double alpha);  power cosine of the same half width
template <typename Model>
struct MicrofacetModel {
  static constexpr ModelFamily kFamily = ModelFamily::kMicrofacet;
  static constexpr int kRhoD = 0;
  static constexpr int kF0 = 3;
  static constexpr int kAlpha = 6;
  static constexpr int kShape = kAlpha;
  static constexpr int kNumParams = 7;
  // alpha = 0 is a mirror, which no BRDF (a function, not a distribution) can represent.
  static constexpr double kMinAlpha = 1e-4;
  static constexpr double kMaxAlpha = 4.0;

  static std::vector<ParamInfo> Params() {
    return {DiffuseAlbedoParam(),
            {"f0", kF0, 3, 0.0, 1.0, 0.04, "Fresnel reflectance at normal incidence (RGB)"},
            {"alpha", kAlpha, 1, kMinAlpha, kMaxAlpha, 0.1,
             "roughness (rms slope for beckmann; larger is broader)"}};
  }

  // The angles the lobe depends on, for wi and wo above the horizon: theta_i, theta_o, theta_d
  // (wi to the half vector h = normalize(wi + wo)) and theta_h (h to the normal).
  template <typename D>
  struct HalfAngles {
    D cos_theta_i, cos_theta_o, cos_theta_d, cos_theta_h;
  };
  template <typename D>
  static HalfAngles<D> Angles(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    using std::sqrt;
    const Vec3T<D> sum = wi + wo;
    const Vec3T<D> half_vector = sum / D(sqrt(sum.squaredNorm()));
    return {CosTheta(wi), CosTheta(wo), wi.dot(half_vector), CosTheta(half_vector)};
  }
  // D G2 / (4 cos theta_i cos theta_o): the lobe without Fresnel, a function of alpha alone
  // for given angles (the fitter differentiates it with a one-variable Jet).
  template <typename T, typename D>
  static T Specular(const HalfAngles<D>& angles, const T& alpha) {
    const T distribution = Model::template D<T>(angles.cos_theta_h, alpha);
    // Height-correlated Smith G2 (Heitz, "Understanding the masking-shadowing function in
    // microfacet-based BRDFs", JCGT 3(2), 2014, eq. 99).
    const T masking = T(1) / (T(1) + Model::template Lambda<T>(angles.cos_theta_i, alpha) +
                              Model::template Lambda<T>(angles.cos_theta_o, alpha));
    return distribution * masking / T(4 * angles.cos_theta_i * angles.cos_theta_o);
  }

  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    const HalfAngles<D> angles = Angles(wi, wo);
    return Value(params, Specular(angles, params[kAlpha]), angles.cos_theta_d);
  }
  // f from the lobe without Fresnel (Specular) and cos theta_d: Eval's last step, and the
  // renderer's once a batch's angular parts are known (render/material.cpp).
  template <typename T, typename D>
  static RgbT<T> Value(const T* params, const T& specular, const D& cos_theta_d) {
    RgbT<T> f;
    for (int c = 0; c < 3; ++c) {
      f[c] =
          params[kRhoD + c] * T(kInvPi) + SchlickFresnel(cos_theta_d, params[kF0 + c]) * specular;
    }
    return f;
  }

  static LobeCoordinates Lobe(const double* params) {
    return {LobeFrame::kHalfVector, params[kAlpha], &Model::kLobeDistribution};
  }
  // The lobe's weight in an importance mixture: Schlick's F averaged over the cosine-weighted
  // hemisphere, f0 + (1 - f0) ∫ (1-c)^5 2c dc = f0 + (1 - f0)/21.
  static Rgb LobeWeight(const double* params) {
    const Rgb f0 = LoadRgb(params, kF0);
    return f0 + (1.0 - f0) / 21.0;
  }
  static double EquivalentExponent(const double* params) {
    return Model::AlphaEquivalentExponent(params[kAlpha]);
  }
};

}  // namespace brdf::models
