// Pieces shared by the templated reflectance models of DESIGN §2. Every model evaluates
// f(wi, wo) in sr^-1 without the cosine factor, zero below the horizon (DESIGN §1), from a
// flat parameter array; models with a lobe share one slot layout so that fitters and the
// registry can name the slots instead of using bare indices.
#pragma once

#include <algorithm>
#include <cmath>
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

// Every model takes a diffuse albedo first. Albedos are not capped at 1 here: a non-conserving
// material must be expressible so that `brdf energy` can show that it is not conserving.
inline ParamInfo DiffuseAlbedoParam() {
  return {"rho_d", 0, 3, 0.0, std::numeric_limits<double>::infinity(), 0.5, "diffuse albedo (RGB)"};
}

// The slots of a composition of a diffuse term and one lobe (composition.h): rho_d (RGB), the
// lobe's per-channel parameter (rho_s or f0, RGB), its shape (an exponent or alpha). The model
// names of DESIGN §2's first table (phong, ggx, ...) are such compositions.
struct SingleLobeSlots {
  static constexpr int kRhoS = 3;
  static constexpr int kF0 = 3;
  static constexpr int kExponent = 6;
  static constexpr int kAlpha = 6;
  static constexpr int kShape = 6;
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
// The same in single precision (the preview renderer's, render/material.cpp) as exp(e ln x)
// through the branch-free polynomials of core/float_math.h, so that a loop over a batch of
// directions vectorizes (libm's powf, a call, was 15 % of a glossy render). The relative error,
// a few times |e ln x| 2^-24, is of the size rounding x to float already costs (its last bit
// raised to the power e; render/material.cpp bounds e for float). 0 below the normal floats.
inline float ClampedPow(float x, float e) {
  const float power = ExpNonPositive(e * LogPositive(std::max(x, 1.17549435e-38f)));  // FLT_MIN
  return x >= 1.17549435e-38f ? power : 0.0f;
}

}  // namespace brdf::models
