// How the fitter's free variables map to model parameters (DESIGN §6).
//
// Ceres offers box bounds only, but the energy bound rho_d + A(m) rho_s <= 1 (energy_bound.h)
// couples parameters. So the fitter works in variables for which every value is a physically
// valid, energy-conserving material, and Ceres never has to enforce the constraint:
//   q_c   = logistic(s_c)         fraction of the albedo budget taken by the lobe, (0, 1)
//   rho_s = q_c / A(m)            so A(m) rho_s = q_c < 1
//   rho_d = (1 - q_c) logistic(d_c)   so rho_d + A(m) rho_s < 1
//   m     = exp(log_m)            the exponent in log space, bounded to [1, 1e6]
// The logistic ("log-odds") variables keep rho_d and rho_s positive as log space would, and
// bounded as the energy budget requires. For lambert only rho_d_c = logistic(d_c) remains.
// `grey_specular` shares one s for all channels (one rho_s, as for dielectric coatings).
#pragma once

#include <cmath>

#include "fitters/energy_bound.h"
#include "models/common.h"

namespace brdf::fitters {

// Slots of the fitter's variables; parameter blocks are d[3], s[1 or 3], log_m[1].
struct FitVariables {
  static constexpr double kLogisticBound = 40.0;  // logistic(-40) = 4e-18: "zero" is reachable
  static constexpr double kMinExponent = 1.0;
  static constexpr double kMaxExponent = 1e6;
};

template <typename T>
T Logistic(const T& x) {
  using std::exp;
  return T(1) / (T(1) + exp(-x));
}

inline double Logit(double p) { return std::log(p / (1.0 - p)); }

// Fills params[LobedSlots] (or params[kRhoD..] for lambert) from the fitter's variables.
template <typename T>
void VariablesToParams(LobeKind kind, bool grey_specular, const T* d, const T* s, const T* log_m,
                       T* params) {
  using std::exp;
  if (kind == LobeKind::kNone) {
    for (int c = 0; c < 3; ++c) params[models::LobedSlots::kRhoD + c] = Logistic(d[c]);
    return;
  }
  const T exponent = exp(log_m[0]);
  const T lobe_albedo = LobeAlbedoAtNormal(kind, exponent);
  for (int c = 0; c < 3; ++c) {
    const T q = Logistic(s[grey_specular ? 0 : c]);
    params[models::LobedSlots::kRhoS + c] = q / lobe_albedo;
    params[models::LobedSlots::kRhoD + c] = (T(1) - q) * Logistic(d[c]);
  }
  params[models::LobedSlots::kExponent] = exponent;
}

}  // namespace brdf::fitters
