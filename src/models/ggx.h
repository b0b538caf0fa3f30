// ggx: the lobe F(wi·h) D(h) G2(wi, wo) / (4 cos theta_i cos theta_o), the microfacet lobe of
// microfacet.h with the Trowbridge-Reitz distribution (Trowbridge & Reitz 1975; named GGX by
// Walter, Marschner, Li & Torrance, "Microfacet models for refraction through rough surfaces",
// EGSR 2007):
//   D(h) = α² / (π (cos²theta_h (α² − 1) + 1)²),
//   Λ(w) = (−1 + sqrt(1 + α² tan²theta)) / 2.
//
// The model `ggx` is lambert+ggx: f = rho_d/π + the lobe.
// Parameters: f0 (RGB in [0, 1], default 0.04), alpha (default 0.1); the model adds rho_d.
// Example: `ggx:rho_d=0.2,0.05,0.05:f0=0.04:alpha=0.08`.
//
// D's tails fall as tan^-4(theta_h), far slower than Beckmann's Gaussian: a glossy coating's
// haze. ∫ D cos(theta_h) dω_h = 1 (the tests check it), so D cos(theta_h) is a density of half
// vectors, and its CDF in theta_h is tan²/(α² + tan²): the samplers invert it.
#pragma once

#include <Eigen/Geometry>

#include "models/microfacet.h"

namespace brdf::models {

struct GgxLobe : MicrofacetLobe<GgxLobe> {
  static constexpr const char* kName = "ggx";
  static constexpr const char* kFormula =
      "F D G2 / (4 cos_i cos_o); D = a^2/(pi (cos^2 h (a^2-1)+1)^2), Schlick F, "
      "height-correlated Smith G2";

  template <typename T, typename Dir>
  static T D(const Dir& cos_theta_h, const T& alpha) {
    const T alpha2 = alpha * alpha;
    const T denominator = T(cos_theta_h * cos_theta_h) * (alpha2 - T(1)) + T(1);
    return alpha2 / (T(kPi) * denominator * denominator);
  }

  template <typename T, typename Dir>
  static T Lambda(const Dir& cos_theta, const T& alpha) {
    return LambdaOfRoughSlope(alpha * alpha * T(TanSquared(cos_theta)));
  }
  // Λ from α² tan²theta: the surface's slope variance along the direction's azimuth over its
  // cotangent squared. An anisotropic surface projects its two alphas on the azimuth (Heitz 2014,
  // eq. 80: α(φ)² = cos²φ α_x² + sin²φ α_y²), so ggx_aniso.h calls this with its own product.
  template <typename T>
  static T LambdaOfRoughSlope(const T& alpha2_tan2) {
    using std::sqrt;
    return (sqrt(T(1) + alpha2_tan2) - T(1)) * T(0.5);
  }

  // The half-vector density D cos(theta_h): mass beyond theta_h is α²/(α² + tan²theta_h).
  static double MassBeyond(double cos_h, double alpha) {
    const double a2c2 = alpha * alpha * cos_h * cos_h;
    return a2c2 / (a2c2 + 1.0 - cos_h * cos_h);
  }
  static double CosAt(double u, double alpha) {
    return std::sqrt(u / (u + alpha * alpha * (1.0 - u)));
  }
  // Templated so that the preview renderer's hot loop draws and weighs in float (models/lobe.h).
  template <typename T>
  static T Density(T cos_h, T alpha) {
    return D(cos_h, alpha) * cos_h;
  }

  // The normals visible from wo, D_wo(h) = G1(wo) max(0, wo.h) D(h) / cos(theta_o), sampled
  // after Heitz, "Sampling the GGX distribution of visible normals", JCGT 7(4), 2018: stretch
  // wo to the configuration where alpha = 1 (there the visible normals are a hemisphere seen
  // from wo), draw a point on the projected disk with the part hidden behind the hemisphere's
  // rim folded onto the visible part, lift it to the hemisphere and unstretch the normal.
  // Templated like Density. The stretched view and its tangent frame depend on wo alone: a
  // batch of draws for one wo shares them. The stretch may differ along x and y (an anisotropic
  // surface, ggx_aniso.h, in its own tangent frame): the paper's method is written for both.
  template <typename T>
  struct VisibleNormalFrame {
    Vec3T<T> view, t1, t2;
    T alpha_x, alpha_y;
  };
  template <typename T>
  static VisibleNormalFrame<T> VisibleNormalFrameOf(const Vec3T<T>& wo, T alpha) {
    return VisibleNormalFrameOf(wo, alpha, alpha);
  }
  template <typename T>
  static VisibleNormalFrame<T> VisibleNormalFrameOf(const Vec3T<T>& wo, T alpha_x, T alpha_y) {
    using std::sqrt;
    const Vec3T<T> view = Vec3T<T>(alpha_x * wo.x(), alpha_y * wo.y(), wo.z()).normalized();
    const T length2 = view.x() * view.x() + view.y() * view.y();
    const Vec3T<T> t1 =
        length2 > T(0) ? Vec3T<T>(-view.y(), view.x(), T(0)) / sqrt(length2) : Vec3T<T>(1, 0, 0);
    return {view, t1, view.cross(t1), alpha_x, alpha_y};
  }
  // sin and cos of the turn u1 (phi = 2 pi u1): libm's in double, the branch-free polynomial
  // (core/float_math.h) in float, so that a batch of draws vectorizes.
  static void SinCosOfTurn(double u1, double* sine, double* cosine) {
    *sine = std::sin(2.0 * kPi * u1);
    *cosine = std::cos(2.0 * kPi * u1);
  }
  static void SinCosOfTurn(float u1, float* sine, float* cosine) { SinCosTurn(u1, sine, cosine); }
  template <typename T>
  static Vec3T<T> SampleVisibleNormal(const VisibleNormalFrame<T>& frame, T u0, T u1) {
    using std::sqrt;
    T sin_phi, cos_phi;
    SinCosOfTurn(u1, &sin_phi, &cos_phi);
    const T radius = sqrt(u0);
    const T p1 = radius * cos_phi;
    const T blend = T(0.5) * (T(1) + frame.view.z());
    const T p2 = (T(1) - blend) * sqrt(std::max(T(0), T(1) - p1 * p1)) + blend * radius * sin_phi;
    const Vec3T<T> normal =
        p1 * frame.t1 + p2 * frame.t2 + sqrt(std::max(T(0), T(1) - p1 * p1 - p2 * p2)) * frame.view;
    // Divided by its length without Eigen's test for a zero vector (normalized()), which would
    // keep a batch of draws scalar: the length is at least cos(theta_h) > 0 for wo above the
    // surface.
    const Vec3T<T> unstretched(frame.alpha_x * normal.x(), frame.alpha_y * normal.y(),
                               std::max(T(0), normal.z()));
    return unstretched / sqrt(unstretched.squaredNorm());
  }
  static Vec3 SampleVisibleNormal(const Vec3& wo, double u0, double u1, double alpha) {
    return SampleVisibleNormal(VisibleNormalFrameOf(wo, alpha), u0, u1);
  }
  // A batch of draws in float for one wo (the renderer's, models/lobe.h); in ggx.cpp, which is
  // compiled so that its loop vectorizes.
  static void SampleVisibleNormals(const Vec3T<float>& wo, const float* u0, const float* u1,
                                   int count, float* x, float* y, float* z, float alpha);
  static double VisibleNormalDensity(const Vec3& wo, const Vec3& h, double alpha) {
    const double wo_dot_h = wo.dot(h);
    if (!(wo.z() > 0.0) || !(h.z() > 0.0) || !(wo_dot_h > 0.0)) return 0.0;
    return D(h.z(), alpha) * wo_dot_h / ((1.0 + Lambda(wo.z(), alpha)) * wo.z());
  }
  static constexpr LobeDistribution kLobeDistribution = {
      "ggx",           MassBeyond,          CosAt,
      Density<double>, SampleVisibleNormal, VisibleNormalDensity,
      Density<float>,  SampleVisibleNormals};

  // D falls to half its peak at tan²theta_h = (√2 − 1) α², where cos^e does for
  // e = 2 ln 2 / ((√2 − 1) α²).
  static double AlphaEquivalentExponent(double alpha) {
    return 2.0 * std::log(2.0) / ((std::sqrt(2.0) - 1.0) * alpha * alpha);
  }
};

}  // namespace brdf::models
