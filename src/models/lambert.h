// lambert: f = rho_d / pi.
//
// Parameters: rho_d (RGB, diffuse albedo, default 0.5).
// Example: `lambert:rho_d=0.8,0.2,0.1`.
// The directional albedo is exactly rho_d at every incidence (∫ cos dω = π, DESIGN §1), so
// the lecture's condition π·C_d <= 1 with C_d = rho_d/π is rho_d <= 1.
#pragma once

#include "models/common.h"

namespace brdf::models {

struct Lambert {
  static constexpr const char* kName = "lambert";
  static constexpr int kRhoD = 0;
  static constexpr int kNumParams = 3;

  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    return LoadRgb(params, kRhoD) * T(kInvPi);
  }
};

}  // namespace brdf::models
