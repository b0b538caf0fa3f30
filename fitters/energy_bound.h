// The energy bound a fit must respect (DESIGN §6): no fitted material may have directional
// albedo > 1 in any channel. Each model family bounds its largest albedo over incidence:
//
// Power-cosine models: the albedo is largest at normal incidence, so the bound is
//   rho_d + A(exponent) * rho_s <= 1,
// with A the normal-incidence lobe albedo per unit rho_s (Model::NormalLobeAlbedo):
//   phong, blinn-phong-exact: A = 1 exactly (their normalizations are built for it);
//   blinn-phong: A(m) = (m+8)(2^(-m/2)+m)/((m+2)(m+4)) (see src/models/blinn_phong.h), which
//   peaks at 1.0752 near m = 8.76, so rho_d + rho_s <= 1 would let it exceed 1.
// Why normal incidence is the maximum: at oblique incidence part of each lobe falls below the
// horizon (phong, and the tests check that its albedo decreases with theta), and for the
// Blinn family the half-vector Jacobian 4 (wi.h) shrinks with theta_i as well; a brute-force
// integration over m = 1 ... 1000 and theta_i = 0 ... 89 degrees found no exception
// (docs/fitting.md).
//
// Microfacet models: Fresnel makes the lobe's albedo rise toward grazing, so the bound is
//   rho_d + max over theta of E(theta; alpha, f0) <= 1,
// with E tabulated from the model itself (microfacet_bound.h).
#pragma once

#include "fitters/microfacet_bound.h"
#include "models/common.h"
#include "models/registry.h"

namespace brdf::fitters {

// The lobe's largest albedo over incidence per channel, for model M's parameters (0 for a
// diffuse model).
template <typename M>
Rgb MaxLobeAlbedo(const double* params) {
  using models::ModelFamily;
  if constexpr (M::kFamily == ModelFamily::kPowerCosine) {
    return models::LoadRgb(params, M::kRhoS) * M::NormalLobeAlbedo(params[M::kExponent]);
  } else if constexpr (M::kFamily == ModelFamily::kMicrofacet) {
    const MicrofacetAlbedoTable& table = AlbedoTableOf<M>();
    const double log_alpha = std::log(params[M::kAlpha]);
    Rgb albedo;
    for (int c = 0; c < 3; ++c) albedo[c] = table.MaxLobeAlbedo(log_alpha, params[M::kF0 + c]);
    return albedo;
  } else {
    return Rgb::Zero();
  }
}

// The bound the fit enforced: rho_d + the lobe's largest albedo, per channel.
template <typename M>
Rgb EnergyBound(const double* params) {
  return models::LoadRgb(params, 0) + MaxLobeAlbedo<M>(params);
}

// The same for a model chosen at run time.
Rgb EnergyBound(const Model& model);

// How the bound is formed, for the report: "rho_d + A(m) rho_s" and so on.
const char* EnergyBoundFormula(models::ModelFamily family);

}  // namespace brdf::fitters
