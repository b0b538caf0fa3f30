// blinn-phong: the lobe rho_s (m+8)/(8 pi) cos^m(theta_h), theta_h = angle between the
// half vector and the normal: the "energy-conserving Blinn-Phong" of real-time rendering
// (Akenine-Möller, Haines & Hoffman, Real-Time Rendering, 3rd ed., §7.6).
//
// The model `blinn-phong` is lambert+blinn-phong: f = rho_d/pi + the lobe.
// Parameters: rho_s (RGB, default 0.04), m (exponent, default 100); the model adds rho_d.
// Example: `blinn-phong:rho_d=0.5,0.1,0.1:rho_s=0.04:m=200`.
//
// (m+8)/(8 pi) is an approximation. The exact normal-incidence lobe albedo is
//   A(m) = rho_s (m+8)(2^(-m/2) + m) / ((m+2)(m+4))
// (see blinn_phong_exact.h for the integral), which peaks at 1.0752 rho_s near m = 8.8, so an
// energy constraint must use that true maximum, not rho_d + rho_s <= 1. The radiometry lecture
// this product grew from prints the factor as (m+8)/pi: eight times too large, an albedo of
// about 8 at normal incidence, which `brdf energy` exposes (rho_s = 8 reproduces it).
#pragma once

#include "models/power_cosine.h"

namespace brdf::models {

struct BlinnPhongLobe : PowerCosineLobe<BlinnPhongLobe> {
  static constexpr const char* kName = "blinn-phong";
  static constexpr const char* kFormula = "rho_s (m+8)/(8pi) cos^m(theta_h)";
  static constexpr const char* kExponentName = "m";
  // cos^m(theta_h): a power-cosine lobe of the half vector about the normal.
  static constexpr LobeFrame kFrame = kHalfVectorFrame;

  // Normal-incidence lobe albedo per unit rho_s, A(m) above (templated for Ceres Jets).
  template <typename T>
  static T NormalLobeAlbedo(const T& m) {
    using std::pow;
    return (m + T(8)) * (pow(T(2), -m / T(2)) + m) / ((m + T(2)) * (m + T(4)));
  }
  // The lobe's cosine, cos(theta_h), and its normalization (m+8)/(8 pi).
  template <typename D>
  static D LobeCosine(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    return CosThetaHalf(wi, wo);
  }
  template <typename T>
  static T LobeNormalization(const T& m) {
    return (m + T(8)) * T(0.125 * kInvPi);
  }

  // cos(theta_h) = z-component of normalize(wi + wo).
  template <typename D>
  static D CosThetaHalf(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    using std::sqrt;
    const Vec3T<D> sum = wi + wo;
    const D norm_squared = sum.squaredNorm();
    if (norm_squared <= D(0)) return D(0);
    return sum.z() / sqrt(norm_squared);
  }
};

// Normal-incidence lobe albedo of blinn-phong per unit rho_s (the closed form above).
inline double BlinnPhongNormalAlbedo(double m) { return BlinnPhongLobe::NormalLobeAlbedo(m); }

}  // namespace brdf::models
