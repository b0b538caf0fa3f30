// phong: the lobe rho_s (n+2)/(2 pi) cos^n(alpha), alpha = angle between wo and the
// mirror direction of wi (the modified Phong model of Lafortune & Willems 1994).
//
// The model `phong` is lambert+phong: f = rho_d/pi + the lobe.
// Parameters: rho_s (RGB, default 0.04), n (exponent, default 100); the model adds rho_d.
// Example: `phong:rho_d=0.3:rho_s=0.2:n=50`.
//
// Why (n+2)/(2 pi): at normal incidence the mirror direction is the normal, alpha = theta_o,
// and the lobe albedo is rho_s (n+2)/(2 pi) * 2 pi ∫0^{pi/2} cos^{n+1}θ sinθ dθ = rho_s exactly.
// At oblique incidence part of the lobe falls below the horizon, so the albedo is smaller:
// rho_d + rho_s <= 1 is the exact energy condition.
#pragma once

#include "models/power_cosine.h"

namespace brdf::models {

struct PhongLobe : PowerCosineLobe<PhongLobe> {
  static constexpr const char* kName = "phong";
  static constexpr const char* kFormula = "rho_s (n+2)/(2pi) cos^n(alpha)";
  static constexpr const char* kExponentName = "n";
  // The lobe is a power cosine about the mirror direction, exactly the sampler's density.
  static constexpr LobeFrame kFrame{false, [](const Vec3& wo) { return MirrorDirection(wo); },
                                    "angle from the mirror direction"};

  // Normal-incidence lobe albedo per unit rho_s: 1 by construction (see above), and the
  // largest over incidence.
  template <typename T>
  static T NormalLobeAlbedo(const T&) {
    return T(1);
  }
  // The lobe's cosine, cos(alpha) between wo and wi's mirror direction, and its normalization
  // (n+2)/(2 pi).
  template <typename D>
  static D LobeCosine(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    return MirrorDirection(wi).dot(wo);
  }
  template <typename T>
  static T LobeNormalization(const T& n) {
    return (n + T(2)) * T(0.5 * kInvPi);
  }
};

}  // namespace brdf::models
