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
  static constexpr const char* kFormula = "rho_d/pi";
  static constexpr ModelFamily kFamily = ModelFamily::kDiffuse;
  static constexpr int kRhoD = 0;
  static constexpr int kShape = -1;  // no lobe, no shape parameter
  static constexpr int kNumParams = 3;

  static std::vector<ParamInfo> Params() { return {DiffuseAlbedoParam()}; }
  static LobeCoordinates Lobe(const double*) { return {LobeFrame::kNormal, 1.0}; }
  static Rgb LobeWeight(const double*) { return Rgb::Zero(); }
  static double EquivalentExponent(const double*) { return 0.0; }

  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    return LoadRgb(params, kRhoD) * T(kInvPi);
  }
};

}  // namespace brdf::models
