// retro: the back-scattering lobe rho_r (n+2)/(2 pi) cos^n(beta), beta the angle between wi and
// wo, which peaks where light returns toward its source: retro-reflective tapes and paints
// (glass beads, corner cubes), and the back-scatter of rough dusty surfaces.
//
// The form is the "back vector" substitution of Belcour, Pacanowski, Delahaie, Laville-Geay &
// Eupherte, "BRDF measurements and analysis of retroreflective materials", JOSA A 31(12), 2014:
// a reflection lobe keeps its shape but is centred on wi itself instead of on the mirror
// direction (or, for a half-vector lobe, on the back vector normalize(wi + mirror(wo))). The ALTA
// library, which published the CEA measurements of that paper, fits its retro-reflection
// models in that form; here the substitution is applied to the modified Phong lobe of phong.h,
// whose normalization it keeps.
//
// Composed with a diffuse term and, if wanted, a specular lobe: `lambert+retro`,
// `lambert+retro+ggx`. Parameters: rho_r (RGB, default 0.1), n_r (exponent, default 10).
// Example: `lambert+retro:rho_d=0.2:rho_r=0.3:n_r=40`.
//
// Energy: at normal incidence wi is the normal and the lobe is phong's about the normal, whose
// albedo is rho_r (n+2)/(2 pi) 2 pi ∫ cos^(n+1) sin = rho_r exactly. At any incidence the lobe is
// the same power cosine about an axis (wi) at the polar angle theta_i, which is phong's lobe
// about the mirror direction (also at theta_i) turned by 180 deg in azimuth; the cosine-weighted
// integral over the hemisphere does not see the azimuth, so the retro lobe's albedo at every
// incidence equals phong's, which falls below rho_r as the lobe leaves the hemisphere (the tests
// check both). The bound is rho_r, reached at normal incidence.
#pragma once

#include <limits>
#include <vector>

#include "models/power_cosine.h"

namespace brdf::models {

struct RetroLobe : PowerCosineLobe<RetroLobe> {
  static constexpr const char* kName = "retro";
  static constexpr const char* kFormula = "rho_r (n_r+2)/(2pi) cos^n_r(wi.wo)";
  static constexpr const char* kBoundFormula = "rho_r";
  static constexpr const char* kAdds = "back-scattering lowers";
  static constexpr const char* kExponentName = "n_r";
  // A power cosine about wi itself (in wo; by reciprocity the same about wo in wi): the
  // samplers draw exactly the lobe's density.
  static constexpr LobeFrame kFrame{false, [](const Vec3& wo) { return wo; },
                                    "angle from the incident direction"};

  static std::vector<ParamInfo> Params() {
    return {{"rho_r", kRhoS, 3, 0.0, std::numeric_limits<double>::infinity(), 0.1,
             "back-scattering (retro-reflection) albedo at normal incidence (RGB)"},
            {kExponentName, kExponent, 1, 0.0, 1e6, 10.0,
             "back-scattering exponent (larger is narrower)"}};
  }

  // Normal-incidence lobe albedo per unit rho_r: 1 (see above), the largest over incidence.
  template <typename T>
  static T NormalLobeAlbedo(const T&) {
    return T(1);
  }
  // cos(beta) = wi.wo, symmetric in the two directions (reciprocity), and (n+2)/(2 pi).
  template <typename D>
  static D LobeCosine(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    return wi.dot(wo);
  }
  template <typename T>
  static T LobeNormalization(const T& n) {
    return (n + T(2)) * T(0.5 * kInvPi);
  }
};

}  // namespace brdf::models
