// What the power-cosine lobes (phong.h, blinn_phong.h, blinn_phong_exact.h) share: the lobe
// rho_s N(e) c^e with c the lobe's cosine (Derived::LobeCosine) and N its normalization
// (Derived::LobeNormalization), e the exponent; and the term interface of term.h built on them.
// Derived (CRTP) also supplies kName, kFormula, kExponentName, kFrame and NormalLobeAlbedo(e),
// the lobe's albedo per unit rho_s at normal incidence, which is its largest (the energy bound).
//
// Parameters: rho_s (RGB, default 0.04), the exponent (default 100).
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "models/term.h"

namespace brdf::models {

template <typename Derived>
struct PowerCosineLobe {
  static constexpr bool kDiffuse = false;
  static constexpr int kRhoS = 0;
  static constexpr int kExponent = 3;
  static constexpr int kShapeSlot = kExponent;
  static constexpr int kNumParams = 4;
  static constexpr ShapeScale kShapeScale = ShapeScale::kExponent;
  static constexpr const char* kBoundFormula = "A(m) rho_s";
  // What the lobe brings to a fit, for `auto`'s sentence ("... lowers the rmse").
  static constexpr const char* kAdds = "the lobe lowers";
  // Whether the energy bound is tabulated by the fitter (fitters/microfacet_bound.h) rather
  // than closed-form.
  static constexpr bool kTabulatedBound = false;
  // Entries of ValueAndGradient's gradient per channel: one per row of the parameter table.
  static constexpr int kGradientSize = 2;
  // rho_s = 0 leaves no lobe (and an exponent that shapes nothing).
  static constexpr bool kVanishesAtZero = true;
  static constexpr double kFitShapeMin = kMinFitExponent;
  static constexpr double kFitShapeMax = kMaxFitExponent;

  static std::vector<ParamInfo> Params() {
    return {{"rho_s", kRhoS, 3, 0.0, std::numeric_limits<double>::infinity(), 0.04,
             "specular lobe albedo scale (RGB)"},
            {Derived::kExponentName, kExponent, 1, 0.0, 1e6, 100.0,
             "lobe exponent (larger is sharper)"}};
  }
  static LobeCoordinates Lobe(const double* params) { return {Derived::kFrame, params[kExponent]}; }
  static Rgb LobeWeight(const double* params) {
    return LoadRgb(params, kRhoS) * Derived::NormalLobeAlbedo(params[kExponent]);
  }
  static double EquivalentExponent(const double* params) { return params[kExponent]; }
  // The largest albedo over incidence per channel: at normal incidence, A(e) rho_s.
  template <typename Bound>
  static Rgb MaxAlbedo(const double* params, const Bound&) {
    return LoadRgb(params, kRhoS) * Derived::NormalLobeAlbedo(params[kExponent]);
  }

  template <typename T>
  struct Part {
    T lobe;  // N(e) c^e
  };
  template <typename T, typename D>
  static Part<T> Angular(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    const T& e = params[kExponent];
    return {Derived::LobeNormalization(e) * ClampedPow(Derived::LobeCosine(wi, wo), e)};
  }
  template <typename T>
  static RgbT<T> Colour(const T* params, const Part<T>& part) {
    return LoadRgb(params, kRhoS) * part.lobe;
  }
  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    return Colour(params, Angular(params, wi, wo));
  }

  // d f_c / d rho_s_c = L and d f_c / d e = rho_s_c (N'(e) c^e + L ln c), L = N(e) c^e, since
  // d c^e / d e = c^e ln c (c > 0; L = 0 and so its derivative for c <= 0). N and N' are the
  // point's (one Jet, Prepare); ln c is the sample's (Geometry: it depends on the directions
  // alone), so c^e = exp(e ln c) costs one exp where pow(c, e) cost a logarithm and an exp.
  struct Prepared {
    ceres::Jet<double, 1> normalization{0.0};
  };
  static Prepared Prepare(const double* params) {
    return {Derived::LobeNormalization(ceres::Jet<double, 1>(params[kExponent], 0))};
  }
  struct Geometry {
    double log_cosine;  // ln c; -infinity for c <= 0 (no lobe)
  };
  static Geometry GeometryOf(const Vec3& wi, const Vec3& wo) {
    const double cosine = Derived::LobeCosine(wi, wo);
    return {cosine > 0 ? std::log(cosine) : -std::numeric_limits<double>::infinity()};
  }
  static double Power(const double* params, const Geometry& geometry) {
    return geometry.log_cosine > -std::numeric_limits<double>::infinity()
               ? std::exp(params[kExponent] * geometry.log_cosine)
               : 0.0;
  }
  static Rgb Value(const double* params, const Prepared& prepared, const Geometry& geometry) {
    return LoadRgb(params, kRhoS) * (prepared.normalization.a * Power(params, geometry));
  }
  static void ValueAndGradient(const double* params, const Prepared& prepared,
                               const Geometry& geometry, Rgb* f, double gradient[3][2]) {
    const double power = Power(params, geometry);
    const double lobe = prepared.normalization.a * power;
    const double slope =
        power > 0 ? prepared.normalization.v[0] * power + lobe * geometry.log_cosine : 0.0;
    for (int c = 0; c < 3; ++c) {
      (*f)[c] = params[kRhoS + c] * lobe;
      gradient[c][0] = lobe;
      gradient[c][1] = params[kRhoS + c] * slope;
    }
  }

  // The fitter's variables s[1 or 3] and shape[1] (parameterization.h):
  //   e = exp(shape), q_c = logistic(s_c) budget_c the share of the albedo the lobe takes,
  //   rho_s_c = q_c / A(e), so that A(e) rho_s_c = q_c.
  static int NumVariables(bool grey) { return (grey ? 1 : 3) + 1; }
  static void VariableBounds(bool grey, double* lower, double* upper) {
    LobeVariableBounds(grey, kFitShapeMin, kFitShapeMax, lower, upper);
  }
  // A share of any budget, down to nothing: the lobe may follow another (models/term.h).
  static constexpr bool kFitsAnyBudget = true;
  template <typename Bound>
  static double LeastAlbedo(const Bound&) {
    return 0.0;
  }
  template <typename T, typename Bound>
  static void Map(const T* variables, bool grey, const T* budget, T* params, T* taken,
                  const Bound&) {
    using std::exp;
    const int s = grey ? 1 : 3;
    const T exponent = exp(variables[s]);
    const T lobe_albedo = Derived::NormalLobeAlbedo(exponent);
    for (int c = 0; c < 3; ++c) {
      taken[c] = Logistic(variables[grey ? 0 : c]) * budget[c];
      params[kRhoS + c] = taken[c] / lobe_albedo;
    }
    params[kExponent] = exponent;
  }
  template <typename Bound>
  static void Unmap(const double* params, bool grey, const double* budget, double* variables,
                    double* taken, const Bound&) {
    const double shape =
        std::clamp(std::log(params[kExponent]), std::log(kFitShapeMin), std::log(kFitShapeMax));
    const double lobe_albedo = Derived::NormalLobeAlbedo(std::exp(shape));
    double s[3];
    for (int c = 0; c < 3; ++c) {
      taken[c] = lobe_albedo * params[kRhoS + c];
      s[c] = BoundedLogit(budget[c] > 0 ? taken[c] / budget[c] : 1.0);
    }
    PackShares(s, shape, grey, variables);
  }
  // The start's lobe from the peak's height above the diffuse floor (per channel, the largest
  // value), kept inside the budget; variables[0..2] per channel, variables[3] the shape.
  template <typename Bound>
  static void Guess(const PeakSample& peak, const TermStart& start, const double* budget,
                    const Bound&, double* variables, double* taken) {
    // The lobe's own value at its peak (wi = wo = normal) per unit rho_s.
    const double unit[kNumParams] = {1, 1, 1, start.shape};
    const Vec3 normal(0, 0, 1);
    const double peak_per_rho_s = Eval<double>(unit, normal, normal)[0];
    for (int c = 0; c < 3; ++c) {
      const double rho_s = std::max(peak.channel_max[c] - peak.diffuse[c], 1e-6) / peak_per_rho_s;
      const double q =
          std::clamp(Derived::NormalLobeAlbedo(start.shape) * rho_s, 1e-6, 0.9 * budget[c]);
      variables[c] = Logit(q / budget[c]);
      taken[c] = q;
    }
    variables[3] = std::log(start.shape);
  }
  static std::vector<TermStart> Starts(const StartShapes& shapes) {
    std::vector<TermStart> starts;
    for (double exponent : shapes.Of(kShapeScale)) starts.push_back({exponent, true});
    return starts;
  }
};

}  // namespace brdf::models
