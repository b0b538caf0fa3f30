// The energy bound a fit must respect (DESIGN §6): no fitted material may have directional
// albedo > 1 in any channel. Each term bounds its largest albedo over incidence
// (models/term.h: MaxAlbedo), and the bound of a composition is their sum, which the fitter's
// variables keep below 1 (parameterization.h):
//
// Power-cosine lobes: the albedo is largest at normal incidence, A(exponent) rho_s, with A the
// normal-incidence lobe albedo per unit rho_s (NormalLobeAlbedo):
//   phong, blinn-phong-exact: A = 1 exactly (their normalizations are built for it);
//   blinn-phong: A(m) = (m+8)(2^(-m/2)+m)/((m+2)(m+4)) (see src/models/blinn_phong.h), which
//   peaks at 1.0752 near m = 8.76, so rho_d + rho_s <= 1 would let it exceed 1.
// Why normal incidence is the maximum: at oblique incidence part of each lobe falls below the
// horizon (phong, and the tests check that its albedo decreases with theta), and for the
// Blinn family the half-vector Jacobian 4 (wi.h) shrinks with theta_i as well; a brute-force
// integration over m = 1 ... 1000 and theta_i = 0 ... 89 degrees found no exception
// (docs/fitting.md).
//
// Microfacet lobes: Fresnel makes the lobe's albedo rise toward grazing, so the bound is
// max over theta of E(theta; alpha, f0), tabulated from the lobe itself (microfacet_bound.h).
#pragma once

#include "fitters/parameterization.h"
#include "models/registry.h"

namespace brdf::fitters {

// The bound the fit enforced for model M's parameters: the sum of its terms' largest albedos,
// per channel.
template <typename M>
Rgb EnergyBound(const double* params) {
  Rgb bound = Rgb::Zero();
  M::ForEachTerm([&](auto term, auto index) {
    using Term = decltype(term);
    bound += Term::MaxAlbedo(params + M::kOffsets[index], TabulatedBound<Term>());
  });
  return bound;
}

// The same for a model chosen at run time.
Rgb EnergyBound(const Model& model);

}  // namespace brdf::fitters
