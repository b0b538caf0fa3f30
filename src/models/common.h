// Pieces shared by the templated reflectance models of DESIGN §2. Every model evaluates
// f(wi, wo) in sr^-1 without the cosine factor, zero below the horizon (DESIGN §1), from a
// flat parameter array; models with a lobe share one slot layout so that fitters and the
// registry can name the slots instead of using bare indices.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/float_math.h"
#include "core/vec.h"
#include "models/lobe.h"

namespace brdf {

// One row of a model's parameter table (each model header owns its table: Model::Params()).
struct ParamInfo {
  std::string name;    // as written in model strings and reports, e.g. "rho_d"
  int slot = 0;        // first index in the flat parameter array
  int channels = 1;    // 3 for RGB parameters
  double lower = 0.0;  // accepted range (inclusive)
  double upper = 0.0;
  double default_value = 0.0;
  std::string meaning;

  // The value as a person should read it: one within kDisplaySnap (relative to the bound, or
  // absolute for a bound of 0) of a finite bound of its range is that bound. A fit drives an
  // albedo it does not need toward 0 through a logistic share, so it arrives at 1e-17, not at
  // 0; printed so, it reads like a measured quantity. Reports in JSON keep the full value.
  static constexpr double kDisplaySnap = 1e-9;
  static bool Near(double value, double bound) {
    return std::isfinite(bound) &&
           std::abs(value - bound) <= kDisplaySnap * std::max(1.0, std::abs(bound));
  }
  double Displayed(double value) const {
    if (Near(value, lower)) return lower;
    if (Near(value, upper)) return upper;
    return value;
  }
  bool AtBound(double value) const { return Near(value, lower) || Near(value, upper); }
};

}  // namespace brdf

namespace brdf::models {

// What a fitter and a diagnostic need to know of a model's shape, besides its table:
//   kDiffuse      no lobe (lambert);
//   kPowerCosine  rho_d, rho_s, exponent; the lobe albedo per unit rho_s is largest at normal
//                 incidence (Model::NormalLobeAlbedo);
//   kMicrofacet   rho_d, f0, alpha; the lobe albedo depends on incidence through Fresnel and
//                 masking and is tabulated by the fitter (fitters/microfacet_bound.h).
enum class ModelFamily { kDiffuse, kPowerCosine, kMicrofacet };

// Every model takes a diffuse albedo first. Albedos are not capped at 1 here: a non-conserving
// material must be expressible so that `brdf energy` can show that it is not conserving.
inline ParamInfo DiffuseAlbedoParam() {
  return {"rho_d", 0, 3, 0.0, std::numeric_limits<double>::infinity(), 0.5, "diffuse albedo (RGB)"};
}

// Slot layout of the power-cosine models: rho_d (RGB), rho_s (RGB), exponent; and what they
// share: the parameter table (only the exponent's name differs), the lobe's weight and the
// width of the lobe as a power-cosine exponent (the diagnostics' measure).
struct LobedSlots {
  static constexpr ModelFamily kFamily = ModelFamily::kPowerCosine;
  static constexpr int kRhoD = 0;
  static constexpr int kRhoS = 3;
  static constexpr int kExponent = 6;
  static constexpr int kShape = kExponent;
  static constexpr int kNumParams = 7;

  // Exponents up to 1e6 cover real materials (measured lobes reach ~1e5) with room to spare.
  static std::vector<ParamInfo> LobedParams(const char* exponent_name) {
    return {DiffuseAlbedoParam(),
            {"rho_s", kRhoS, 3, 0.0, std::numeric_limits<double>::infinity(), 0.04,
             "specular lobe albedo scale (RGB)"},
            {exponent_name, kExponent, 1, 0.0, 1e6, 100.0, "lobe exponent (larger is sharper)"}};
  }
  static double EquivalentExponent(const double* params) { return params[kExponent]; }
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
// The same in doubles, each thread remembering its last results in a small direct-mapped table
// keyed by the base's bits. Tabulated data repeat their lobe cosines: the 1,096,216 usable cells
// of a MERL table have 354 distinct half-vector cosines, so a blinn-phong fit's pass over them
// (at one exponent) calls pow a few hundred times instead of a million (libm's pow was a fifth
// of such a fit's time). A hit returns what pow returned for those arguments, so the bits are
// pow's; a base that never repeats costs one hash and one compare more.
inline double ClampedPow(double x, double e) {
  if (x <= 0.0) return 0.0;
  struct Entry {
    double x = 0.0, e = 0.0, power = 0.0;  // x = 0 matches no positive base
  };
  constexpr int kBits = 9;
  thread_local Entry memo[1 << kBits];
  uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  Entry& entry = memo[(bits * 0x9e3779b97f4a7c15ull) >> (64 - kBits)];  // Fibonacci hashing
  if (entry.x != x || entry.e != e) entry = {x, e, std::pow(x, e)};
  return entry.power;
}
// The same in single precision (the preview renderer's, render/material.cpp) as exp(e ln x)
// through the branch-free polynomials of core/float_math.h, so that a loop over a batch of
// directions vectorizes (libm's powf, a call, was 15 % of a glossy render). The relative error,
// a few times |e ln x| 2^-24, is of the size rounding x to float already costs (its last bit
// raised to the power e; render/material.cpp bounds e for float). 0 below the normal floats.
inline float ClampedPow(float x, float e) {
  const float power = ExpNonPositive(e * LogPositive(std::max(x, 1.17549435e-38f)));  // FLT_MIN
  return x >= 1.17549435e-38f ? power : 0.0f;
}

// The power-cosine models' common form, f = rho_d/pi + rho_s N(m) c^m: each model supplies its
// lobe cosine c(wi, wo) (M::LobeCosine) and normalization N(m) (M::LobeNormalization). One
// definition for evaluation and for the fitter's analytic derivatives
// (fitters/analytic_cost.h), which take d f / d m = rho_s (N'(m) + N(m) ln c) c^m from the same
// pieces.
template <typename T>
inline RgbT<T> PowerCosineValue(const T* params, const T& lobe) {
  return LoadRgb(params, LobedSlots::kRhoD) * T(kInvPi) + LoadRgb(params, LobedSlots::kRhoS) * lobe;
}
template <typename M, typename T, typename D>
inline RgbT<T> EvalPowerCosine(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
  if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
  const T& m = params[LobedSlots::kExponent];
  const T lobe = M::LobeNormalization(m) * ClampedPow(M::LobeCosine(wi, wo), m);
  return PowerCosineValue(params, lobe);
}

}  // namespace brdf::models
