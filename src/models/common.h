// Pieces shared by the templated reflectance models of DESIGN §2. Every model evaluates
// f(wi, wo) in sr^-1 without the cosine factor, zero below the horizon (DESIGN §1), from a
// flat parameter array; models with a lobe share one slot layout so that fitters and the
// registry can name the slots instead of using bare indices.
#pragma once

#include <cmath>

#include "core/angles.h"
#include "core/vec.h"

namespace brdf::models {

// Slot layout of the lobed models: rho_d (RGB), rho_s (RGB), exponent.
struct LobedSlots {
  static constexpr int kRhoD = 0;
  static constexpr int kRhoS = 3;
  static constexpr int kExponent = 6;
  static constexpr int kNumParams = 7;
};

template <typename T>
inline RgbT<T> LoadRgb(const T* params, int slot) {
  return RgbT<T>(params[slot], params[slot + 1], params[slot + 2]);
}

// Every model is templated on T, the scalar of its parameters, and D, the scalar of the
// directions (deduced). D = T serves plain evaluation and derivatives with respect to
// directions; D = double with T = ceres::Jet lets a fit differentiate only with respect to the
// parameters, computing the geometry once in plain doubles.

// Both directions strictly above the surface; grazing (z = 0) counts as below.
template <typename T>
inline bool AboveHorizon(const Vec3T<T>& wi, const Vec3T<T>& wo) {
  return CosTheta(wi) > T(0) && CosTheta(wo) > T(0);
}

// x^e for x in (0, 1]; 0 for x <= 0. Keeps pow away from 0 so that automatic differentiation
// never evaluates log(0) in the exponent's derivative. The base may be a plain double (the
// geometry) while the exponent is a Jet (a fitted parameter).
template <typename D, typename T>
inline T ClampedPow(const D& x, const T& e) {
  using std::pow;
  if (x <= D(0)) return T(0);
  return pow(x, e);
}

}  // namespace brdf::models
