// lambert: f = rho_d / pi, the diffuse term of a composition (composition.h) and the model
// `lambert` on its own.
//
// Parameters: rho_d (RGB, diffuse albedo, default 0.5).
// Example: `lambert:rho_d=0.8,0.2,0.1`.
// The directional albedo is exactly rho_d at every incidence (∫ cos dω = π, DESIGN §1), so
// the lecture's condition π·C_d <= 1 with C_d = rho_d/π is rho_d <= 1.
#pragma once

#include <algorithm>

#include "models/term.h"

namespace brdf::models {

struct Lambert {
  static constexpr const char* kName = "lambert";
  static constexpr const char* kFormula = "rho_d/pi";
  static constexpr const char* kBoundFormula = "rho_d";
  static constexpr const char* kAdds = "the diffuse term lowers";
  static constexpr bool kDiffuse = true;
  static constexpr int kRhoD = 0;
  static constexpr int kNumParams = 3;
  static constexpr int kShapeSlot = -1;  // no shape parameter
  static constexpr ShapeScale kShapeScale = ShapeScale::kNone;
  // Whether the energy bound is tabulated by the fitter (fitters/microfacet_bound.h) rather
  // than closed-form.
  static constexpr bool kTabulatedBound = false;
  // Entries of ValueAndGradient's gradient per channel: one per row of the parameter table.
  static constexpr int kGradientSize = 1;
  static constexpr bool kVanishesAtZero = true;

  static std::vector<ParamInfo> Params() { return {DiffuseAlbedoParam()}; }
  static LobeCoordinates Lobe(const double*) { return {kNormalFrame, 1.0}; }
  static Rgb LobeWeight(const double* params) { return LoadRgb(params, kRhoD); }
  static double EquivalentExponent(const double*) { return 0.0; }
  // The albedo at every incidence.
  template <typename Bound>
  static Rgb MaxAlbedo(const double* params, const Bound&) {
    return LoadRgb(params, kRhoD);
  }

  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    return LoadRgb(params, kRhoD) * T(kInvPi);
  }

  // Nothing of f depends on the directions above the horizon.
  template <typename T>
  struct Part {};
  template <typename T, typename D>
  static Part<T> Angular(const T*, const Vec3T<D>&, const Vec3T<D>&) {
    return {};
  }
  template <typename T>
  static RgbT<T> Colour(const T* params, const Part<T>&) {
    return LoadRgb(params, kRhoD) * T(kInvPi);
  }
  struct Prepared {};
  static Prepared Prepare(const double*) { return {}; }
  struct Geometry {};
  static Geometry GeometryOf(const Vec3&, const Vec3&) { return {}; }
  static Rgb Value(const double* params, const Prepared&, const Geometry&) {
    return LoadRgb(params, kRhoD) * kInvPi;
  }
  static void ValueAndGradient(const double* params, const Prepared&, const Geometry&, Rgb* f,
                               double gradient[3][1]) {
    for (int c = 0; c < 3; ++c) {
      (*f)[c] = params[kRhoD + c] * kInvPi;
      gradient[c][0] = kInvPi;
    }
  }

  // The fitter's variables d[3]: rho_d_c = budget_c logistic(d_c), the share of the albedo the
  // lobes leave (parameterization.h).
  static int NumVariables(bool) { return 3; }
  static void VariableBounds(bool, double* lower, double* upper) {
    std::fill(lower, lower + 3, -kLogisticBound);
    std::fill(upper, upper + 3, kLogisticBound);
  }
  template <typename T, typename Bound>
  static void Map(const T* variables, bool, const T* budget, T* params, T* taken, const Bound&) {
    for (int c = 0; c < 3; ++c) {
      params[kRhoD + c] = budget[c] * Logistic(variables[c]);
      taken[c] = params[kRhoD + c];
    }
  }
  template <typename Bound>
  static void Unmap(const double* params, bool, const double* budget, double* variables,
                    double* taken, const Bound&) {
    for (int c = 0; c < 3; ++c) {
      variables[c] = BoundedLogit(budget[c] > 0 ? params[kRhoD + c] / budget[c] : 1.0);
      taken[c] = params[kRhoD + c];
    }
  }
  // The start's variables from rho_d read off the diffuse floor, kept inside the budget.
  static void Guess(const Rgb& rho_d, const double* budget, double* variables) {
    for (int c = 0; c < 3; ++c) {
      const double room = std::max(budget[c], 1e-6);
      const double value = std::min(rho_d[c], 0.99 * room);
      variables[c] = Logit(std::clamp(value / room, 1e-6, 1 - 1e-6));
    }
  }
};

}  // namespace brdf::models
