// blinn-phong-exact: the lobe rho_s (m+2)(m+4) / (8 pi (2^(-m/2) + m)) cos^m(theta_h).
//
// The model `blinn-phong-exact` is lambert+blinn-phong-exact: f = rho_d/pi + the lobe.
// Parameters: rho_s (RGB, default 0.04), m (exponent, default 100); the model adds rho_d.
// Example: `blinn-phong-exact:rho_d=0.2:rho_s=0.5:m=1000`.
//
// Why this factor: at normal incidence h = normalize(n + wo) makes theta_h = theta_o / 2, so
//   ∫ cos^m(theta_h) cos(theta_o) dω = 2π ∫0^{π/2} cos^m(θ/2) cosθ sinθ dθ
//                                    = 8π (2^(-m/2) + m) / ((m+2)(m+4))
// (substitute u = cos(θ/2), cosθ = 2u²-1, sinθ dθ = 4u du, integrate u from 1/√2 to 1).
// Dividing by it makes the normal-incidence lobe albedo exactly rho_s, so, as for phong,
// rho_d + rho_s <= 1 bounds the albedo at normal incidence exactly.
#pragma once

#include "models/blinn_phong.h"
#include "models/power_cosine.h"

namespace brdf::models {

struct BlinnPhongExactLobe : PowerCosineLobe<BlinnPhongExactLobe> {
  static constexpr const char* kName = "blinn-phong-exact";
  static constexpr const char* kFormula = "rho_s (m+2)(m+4)/(8pi(2^(-m/2)+m)) cos^m(theta_h)";
  static constexpr const char* kExponentName = "m";
  static constexpr LobeFrame kFrame = kHalfVectorFrame;

  // Normal-incidence lobe albedo per unit rho_s: exactly 1 (the factor above is built for it).
  template <typename T>
  static T NormalLobeAlbedo(const T&) {
    return T(1);
  }
  // The lobe's cosine, cos(theta_h), and the normalization above.
  template <typename D>
  static D LobeCosine(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    return BlinnPhongLobe::CosThetaHalf(wi, wo);
  }
  template <typename T>
  static T LobeNormalization(const T& m) {
    using std::pow;
    return (m + T(2)) * (m + T(4)) / (T(8 * kPi) * (pow(T(2), -m / T(2)) + m));
  }
};

}  // namespace brdf::models
