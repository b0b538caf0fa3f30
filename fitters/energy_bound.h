// The energy bound a fit must respect (DESIGN §6): no fitted material may have directional
// albedo > 1 in any channel.
//
// For every model here the albedo is largest at normal incidence, so the bound is
//   rho_d + A(exponent) * rho_s <= 1,
// with A the normal-incidence lobe albedo per unit rho_s:
//   phong, blinn-phong-exact: A = 1 exactly (their normalizations are built for it);
//   blinn-phong: A(m) = (m+8)(2^(-m/2)+m)/((m+2)(m+4)) (see src/models/blinn_phong.h), which
//   peaks at 1.0752 near m = 8.76, so rho_d + rho_s <= 1 would let it exceed 1.
// Why normal incidence is the maximum: at oblique incidence part of each lobe falls below the
// horizon (phong, and the tests check that its albedo decreases with theta), and for the
// Blinn family the half-vector Jacobian 4 (wi.h) shrinks with theta_i as well; a brute-force
// integration over m = 1 ... 1000 and theta_i = 0 ... 89 degrees found no exception
// (docs/fitting.md).
#pragma once

#include <cmath>
#include <string_view>

#include "models/blinn_phong.h"

namespace brdf::fitters {

enum class LobeKind { kNone, kPhong, kBlinnPhong, kBlinnPhongExact };

LobeKind LobeKindOf(std::string_view model_name);

// Normal-incidence lobe albedo per unit rho_s, templated for Ceres Jets.
template <typename T>
T LobeAlbedoAtNormal(LobeKind kind, const T& exponent) {
  using std::pow;
  if (kind != LobeKind::kBlinnPhong) return T(1);
  return (exponent + T(8)) * (pow(T(2), -exponent / T(2)) + exponent) /
         ((exponent + T(2)) * (exponent + T(4)));
}

}  // namespace brdf::fitters
