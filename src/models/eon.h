// eon: the energy-preserving Oren–Nayar diffuse term of Portsmouth, Kutz & Hill, "EON: A
// practical energy-preserving rough diffuse BRDF", JCGT 14(1), 2025 (the diffuse base of
// OpenPBR), a rough diffuse body (paper, felt, plaster, the moon) that brightens toward the light
// and toward grazing where lambert stays flat.
//
// Parameters: rho_d (RGB, the albedo, default 0.5), sigma (roughness in [0, 1], default 0.5;
// 0 is lambert). Example: `eon+ggx:rho_d=0.6,0.5,0.4:sigma=0.8:f0=0.04:alpha=0.2`.
//
// The single-scattering part is Fujii's improved Oren–Nayar ("FON"), with mu = cos theta:
//   f_ss = rho/pi A (1 + sigma s/t),  s = wi.wo - mu_i mu_o,  t = max(mu_i, mu_o) for s > 0,
//   else 1,  A = 1 / (1 + c1 sigma),  c1 = 1/2 - 2/(3 pi).
// Its directional albedo at rho = 1 is, in closed form (the paper's eq. for E_FON),
//   E(mu) = A (1 + sigma G(mu) / pi),
//   G(mu) = S (acos(mu) - S mu) + (2/3) ((S / mu)(1 - S^3) - S),  S = sqrt(1 - mu^2),
// and its cosine-weighted average is E_avg = A (1 + c2 sigma), c2 = 2/3 - 28/(15 pi). What it
// loses, 1 - E, is given back by the multiple-scattering lobe
//   f_ms = rho_ms/pi (1 - E(mu_o)) (1 - E(mu_i)) / (1 - E_avg),
//   rho_ms = rho^2 E_avg / (1 - rho (1 - E_avg)).
// Written with 1 - E(mu) = A sigma g(mu), g = c1 - G/pi, and 1 - E_avg = A sigma (c1 - c2)
// (derived here from the forms above), f_ms = rho_ms/pi A sigma g(mu_o) g(mu_i) / (c1 - c2): no
// 0/0 at sigma = 0 (lambert), so no clamp. g falls from c1 at the normal to 0 at grazing (G(0) =
// pi/2 - 2/3), so g >= 0 and f_ms >= 0.
//
// Energy (tests: eon_test in model_terms_test.cpp): the albedo is
//   a(mu) = rho E(mu) + rho_ms (1 - E(mu))   (∫ g(mu) 2 mu dmu = c1 - c2),
// and rho_ms <= rho for rho <= 1 (rho E_avg <= 1 - rho + rho E_avg), so a(mu) <= rho, with equality
// at grazing where E = 1; at rho = 1, rho_ms = 1 and a = 1 at every incidence (the white furnace).
// The bound is rho_d, as for lambert, and reached (at grazing): the paper's point. The exact E
// is used, not the paper's polynomial fit of it, whose value at grazing slightly exceeds 1.
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/term.h"

namespace brdf::models {

struct Eon {
  static constexpr const char* kName = "eon";
  static constexpr const char* kFormula =
      "rho_d/pi A (1 + sigma s/t) + rho_ms/pi A sigma g(mu_i) g(mu_o)/(c1-c2) (energy-preserving "
      "Oren-Nayar)";
  static constexpr const char* kBoundFormula = "rho_d";
  static constexpr const char* kAdds = "the rough diffuse term lowers";
  static constexpr bool kDiffuse = true;
  static constexpr int kRhoD = 0;
  static constexpr int kSigma = 3;
  static constexpr int kNumParams = 4;
  // sigma is a logistic share of [0, 1] for the fitter, not a lobe width (held out of the
  // covariance when it saturates, like an albedo).
  static constexpr int kShapeSlot = -1;
  static constexpr ShapeScale kShapeScale = ShapeScale::kNone;
  static constexpr bool kTabulatedBound = false;
  static constexpr int kGradientSize = 2;
  static constexpr bool kVanishesAtZero = true;
  // The start's roughness: between lambert (0) and the paper's roughest (1).
  static constexpr double kStartSigma = 0.5;

  static constexpr double kC1 = 0.5 - 2.0 / (3.0 * kPi);
  static constexpr double kC2 = 2.0 / 3.0 - 28.0 / (15.0 * kPi);

  static std::vector<ParamInfo> Params() {
    // rho_d up to 1: the multiple-scattering albedo rho_ms is the paper's for rho <= 1 (beyond,
    // its denominator 1 - rho (1 - E_avg) reaches 0).
    ParamInfo rho_d = DiffuseAlbedoParam();
    rho_d.upper = 1.0;
    return {rho_d,
            {"sigma", kSigma, 1, 0.0, 1.0, 0.5, "Oren-Nayar roughness (0: lambert, 1: roughest)"}};
  }
  static LobeCoordinates Lobe(const double*) { return {kNormalFrame, 1.0}; }
  static Rgb LobeWeight(const double* params) { return LoadRgb(params, kRhoD); }
  static double EquivalentExponent(const double*) { return 0.0; }
  // The largest albedo over incidence: rho_d, at grazing (see above).
  template <typename Bound>
  static Rgb MaxAlbedo(const double* params, const Bound&) {
    return LoadRgb(params, kRhoD);
  }

  // g(mu) = c1 - G(mu)/pi, the FON albedo's deficit per unit A sigma: 1 - E = A sigma g.
  template <typename D>
  static D AlbedoDeficit(const D& mu) {
    using std::acos;
    using std::sqrt;
    const D sine = sqrt(std::max(D(0), D(1) - mu * mu));
    const D g = sine * (acos(std::min(mu, D(1))) - sine * mu) +
                D(2.0 / 3.0) * ((sine / mu) * (D(1) - sine * sine * sine) - sine);
    return std::max(D(0), D(kC1) - g * D(kInvPi));
  }
  // E(mu) at rho = 1: the FON directional albedo.
  template <typename T, typename D>
  static T FonAlbedo(const D& mu, const T& sigma) {
    return T(1) - sigma * T(AlbedoDeficit(mu)) / (T(1) + T(kC1) * sigma);
  }

  // What depends on the directions: s/t and g(mu_i) g(mu_o).
  template <typename T>
  struct Part {
    T s_over_t, deficits;
  };
  template <typename T, typename D>
  static Part<T> Angular(const T*, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    const D mu_i = CosTheta(wi), mu_o = CosTheta(wo);
    const D s = wi.dot(wo) - mu_i * mu_o;
    const D s_over_t = s > D(0) ? s / std::max(mu_i, mu_o) : s;
    return {T(s_over_t), T(AlbedoDeficit(mu_i) * AlbedoDeficit(mu_o))};
  }
  // f per channel from the part: rho/pi A [(1 + sigma s/t) + rho_ms/rho sigma g_i g_o/(c1-c2)].
  template <typename T>
  static T Channel(const T& rho, const T& sigma, const T& s_over_t, const T& deficits) {
    const T a = T(1) / (T(1) + T(kC1) * sigma);
    const T average = a * (T(1) + T(kC2) * sigma);  // E_avg
    const T rho_ms = rho * rho * average / (T(1) - rho * (T(1) - average));
    return a * T(kInvPi) *
           (rho * (T(1) + sigma * s_over_t) + rho_ms * sigma * deficits / T(kC1 - kC2));
  }
  template <typename T>
  static RgbT<T> Colour(const T* params, const Part<T>& part) {
    RgbT<T> f;
    for (int c = 0; c < 3; ++c) {
      f[c] = Channel(params[kRhoD + c], params[kSigma], part.s_over_t, part.deficits);
    }
    return f;
  }
  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    return Colour(params, Angular<T, D>(params, wi, wo));
  }

  // d f_c / d rho_c and d f_c / d sigma by a two-variable Jet of Channel (one definition).
  struct Prepared {};
  static Prepared Prepare(const double*) { return {}; }
  using Geometry = Part<double>;
  static Geometry GeometryOf(const Vec3& wi, const Vec3& wo) {
    return Angular<double, double>(nullptr, wi, wo);
  }
  static Rgb Value(const double* params, const Prepared&, const Geometry& geometry) {
    return Colour(params, geometry);
  }
  static void ValueAndGradient(const double* params, const Prepared&, const Geometry& geometry,
                               Rgb* f, double gradient[3][2]) {
    using Jet2 = ceres::Jet<double, 2>;
    const Jet2 sigma(params[kSigma], 1);
    for (int c = 0; c < 3; ++c) {
      const Jet2 value = Channel(Jet2(params[kRhoD + c], 0), sigma, Jet2(geometry.s_over_t),
                                 Jet2(geometry.deficits));
      (*f)[c] = value.a;
      gradient[c][0] = value.v[0];
      gradient[c][1] = value.v[1];
    }
  }

  // The fitter's variables d[3] and r: rho_d_c = budget_c logistic(d_c) (as lambert's: the
  // albedo is at most rho_d), sigma = logistic(r).
  static int NumVariables(bool) { return 4; }
  static void VariableBounds(bool, double* lower, double* upper) {
    std::fill(lower, lower + 4, -kLogisticBound);
    std::fill(upper, upper + 4, kLogisticBound);
  }
  template <typename T, typename Bound>
  static void Map(const T* variables, bool, const T* budget, T* params, T* taken, const Bound&) {
    for (int c = 0; c < 3; ++c) {
      params[kRhoD + c] = budget[c] * Logistic(variables[c]);
      taken[c] = params[kRhoD + c];
    }
    params[kSigma] = Logistic(variables[3]);
  }
  template <typename Bound>
  static void Unmap(const double* params, bool, const double* budget, double* variables,
                    double* taken, const Bound&) {
    for (int c = 0; c < 3; ++c) {
      variables[c] = BoundedLogit(budget[c] > 0 ? params[kRhoD + c] / budget[c] : 1.0);
      taken[c] = params[kRhoD + c];
    }
    variables[3] = BoundedLogit(params[kSigma]);
  }
  // The start: rho_d read off the diffuse floor (kept inside the budget), sigma kStartSigma.
  static void Guess(const Rgb& rho_d, const double* budget, double* variables) {
    for (int c = 0; c < 3; ++c) {
      const double room = std::max(budget[c], 1e-6);
      const double value = std::min(rho_d[c], 0.99 * room);
      variables[c] = Logit(std::clamp(value / room, 1e-6, 1 - 1e-6));
    }
    variables[3] = Logit(kStartSigma);
  }
};

}  // namespace brdf::models
