// What the microfacet lobes of DESIGN §2 share: Fresnel (Schlick's approximation, and the
// exact reflectance of a smooth interface that the virtual gonioreflectometer's facets use),
// the height-correlated Smith masking-shadowing term, and the lobe template itself:
//
//   f(wi, wo) = F(wi·h) D(h) G2(wi, wo) / (4 cos theta_i cos theta_o)
//
// with h = normalize(wi + wo), summed with a diffuse term in a composition (composition.h). A
// lobe (ggx.h, beckmann.h) supplies its normal distribution D, its Smith Λ, its name and the
// density the samplers draw half vectors from. Everything is templated on the scalar so that
// one definition serves double and ceres::Jet (STYLE rule 3).
//
// Parameters: f0 (RGB, Fresnel reflectance at normal incidence in [0, 1], default 0.04, a
// dielectric of index 1.5), alpha (roughness, not squared, default 0.1).
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>

#include "models/term.h"

namespace brdf::models {

// Schlick, "An inexpensive BRDF model for physically-based rendering", CGF 13(3), 1994:
// F = f0 + (1 - f0)(1 - cos theta_d)^5, per channel. Linear in f0, which the fitter's energy
// bound uses (fitters/microfacet_bound.h).
template <typename D, typename T>
T SchlickFresnel(const D& cos_theta_d, const T& f0) {
  const D m = cos_theta_d >= D(1) ? D(0) : (cos_theta_d <= D(0) ? D(1) : D(1) - cos_theta_d);
  const D m2 = m * m;
  return f0 + (T(1) - f0) * (m2 * m2 * m);
}

// Exact Fresnel reflectance of a smooth interface from air for unpolarized light, with the
// relative index n + i k (k = 0: a dielectric). Written in real arithmetic (Born & Wolf,
// Principles of Optics, §14.2; the form given by Cook & Torrance 1982 for metals): with
//   a² + b² = sqrt((n² − k² − sin²θ)² + 4 n² k²),   a² = (a² + b² + n² − k² − sin²θ) / 2,
//   R_s = (a² + b² − 2a cos θ + cos²θ) / (a² + b² + 2a cos θ + cos²θ),
//   R_p = R_s ((a² + b²) cos²θ − 2a cos θ sin²θ + sin⁴θ) / ((a² + b²) cos²θ + 2a cos θ sin²θ +
//   sin⁴θ),
// R = (R_s + R_p) / 2. Equal to |r_s|² and |r_p|² of the complex Fresnel amplitudes (the
// surface tests check it against that form); real arithmetic avoids complex sqrt and division
// in the tracer's inner loop.
template <typename T>
T FresnelReflectance(T cos_theta, const T& n, const T& k) {
  using std::sqrt;
  if (cos_theta < T(0)) cos_theta = T(0);
  if (cos_theta > T(1)) cos_theta = T(1);
  const T cos2 = cos_theta * cos_theta, sin2 = T(1) - cos2;
  const T t0 = n * n - k * k - sin2;
  const T a2_plus_b2 = sqrt(t0 * t0 + T(4) * n * n * k * k);
  const T a_squared = T(0.5) * (a2_plus_b2 + t0);
  const T a = a_squared > T(0) ? sqrt(a_squared) : T(0);
  const T r_s_num = a2_plus_b2 - T(2) * a * cos_theta + cos2;
  const T r_s_den = a2_plus_b2 + T(2) * a * cos_theta + cos2;
  const T r_s = r_s_den > T(0) ? r_s_num / r_s_den : T(1);
  const T t1 = a2_plus_b2 * cos2 + sin2 * sin2, t2 = T(2) * a * cos_theta * sin2;
  const T r_p = t1 + t2 > T(0) ? r_s * (t1 - t2) / (t1 + t2) : T(1);
  return T(0.5) * (r_s + r_p);
}

// tan²(theta) of a direction from its cosine; 0 at the normal.
template <typename D>
D TanSquared(const D& cos_theta) {
  const D cos2 = cos_theta * cos_theta;
  return (D(1) - cos2) / cos2;
}

// The lobe template. `Derived` (the lobe, CRTP) provides
//   template <T, D> static T D(const D& cos_theta_h, const T& alpha);    normal distribution
//   template <T, D> static T Lambda(const D& cos_theta, const T& alpha); Smith Λ
//   static const LobeDistribution kLobeDistribution;                      D(h) cos(theta_h)
//   static double AlphaEquivalentExponent(double alpha);  power cosine of the same half width
//
// Its albedo E(theta; alpha, f0) rises toward grazing with Fresnel, so the energy bound is its
// largest value over incidence, which the fitter tabulates from Eval (fitters/microfacet_bound.h:
// the `Bound` of Map, Unmap and Guess). Schlick's F is linear in f0, so E is too.
template <typename Derived>
struct MicrofacetLobe {
  static constexpr bool kDiffuse = false;
  static constexpr int kF0 = 0;
  static constexpr int kAlpha = 3;
  static constexpr int kShapeSlot = kAlpha;
  static constexpr int kNumParams = 4;
  static constexpr ShapeScale kShapeScale = ShapeScale::kRoughness;
  static constexpr const char* kBoundFormula = "max over theta of E(theta; alpha, f0)";
  // What the lobe brings to a fit, for `auto`'s sentence ("... lower the rmse").
  static constexpr const char* kAdds = "Fresnel and masking lower";
  // Whether the energy bound is tabulated by the fitter (fitters/microfacet_bound.h) rather
  // than closed-form.
  static constexpr bool kTabulatedBound = true;
  // The term whose table it is: its own (a lobe bounded by another's table names that one).
  using AlbedoTableTerm = Derived;
  // Entries of ValueAndGradient's gradient per channel: one per row of the parameter table.
  static constexpr int kGradientSize = 2;
  // f0 = 0 still leaves Schlick's rise toward grazing: the lobe never vanishes.
  static constexpr bool kVanishesAtZero = false;
  // alpha = 0 is a mirror, which no BRDF (a function, not a distribution) can represent.
  static constexpr double kMinAlpha = 1e-4;
  static constexpr double kMaxAlpha = 4.0;
  // The fitter's range, that of the tabulated bound.
  static constexpr double kFitShapeMin = kMinFitRoughness;
  static constexpr double kFitShapeMax = kMaxFitRoughness;

  static std::vector<ParamInfo> Params() {
    return {{"f0", kF0, 3, 0.0, 1.0, 0.04, "Fresnel reflectance at normal incidence (RGB)"},
            {"alpha", kAlpha, 1, kMinAlpha, kMaxAlpha, 0.1,
             "roughness (rms slope for beckmann; larger is broader)"}};
  }

  // The angles the lobe depends on, for wi and wo above the horizon: theta_i, theta_o, theta_d
  // (wi to the half vector h = normalize(wi + wo)) and theta_h (h to the normal).
  template <typename D>
  struct HalfAngles {
    D cos_theta_i, cos_theta_o, cos_theta_d, cos_theta_h;
  };
  template <typename D>
  static HalfAngles<D> Angles(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    using std::sqrt;
    const Vec3T<D> sum = wi + wo;
    const Vec3T<D> half_vector = sum / D(sqrt(sum.squaredNorm()));
    return {CosTheta(wi), CosTheta(wo), wi.dot(half_vector), CosTheta(half_vector)};
  }
  // D G2 / (4 cos theta_i cos theta_o): the lobe without Fresnel, a function of alpha alone
  // for given angles (the fitter differentiates it with a one-variable Jet).
  template <typename T, typename D>
  static T Specular(const HalfAngles<D>& angles, const T& alpha) {
    const T distribution = Derived::template D<T>(angles.cos_theta_h, alpha);
    // Height-correlated Smith G2 (Heitz, "Understanding the masking-shadowing function in
    // microfacet-based BRDFs", JCGT 3(2), 2014, eq. 99).
    const T masking = T(1) / (T(1) + Derived::template Lambda<T>(angles.cos_theta_i, alpha) +
                              Derived::template Lambda<T>(angles.cos_theta_o, alpha));
    return distribution * masking / T(4 * angles.cos_theta_i * angles.cos_theta_o);
  }

  template <typename T>
  struct Part {
    T specular;     // D G2 / (4 cos theta_i cos theta_o)
    T cos_theta_d;  // Fresnel's angle
  };
  template <typename T, typename D>
  static Part<T> Angular(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    const HalfAngles<D> angles = Angles(wi, wo);
    return {Specular(angles, params[kAlpha]), T(angles.cos_theta_d)};
  }
  template <typename T>
  static RgbT<T> Colour(const T* params, const Part<T>& part) {
    RgbT<T> f;
    for (int c = 0; c < 3; ++c)
      f[c] = SchlickFresnel(part.cos_theta_d, params[kF0 + c]) * part.specular;
    return f;
  }
  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    const HalfAngles<D> angles = Angles(wi, wo);
    RgbT<T> f;
    const T specular = Specular(angles, params[kAlpha]);
    for (int c = 0; c < 3; ++c)
      f[c] = SchlickFresnel(angles.cos_theta_d, params[kF0 + c]) * specular;
    return f;
  }

  // F_c = f0_c + (1 - f0_c) w, w = (1 - cos theta_d)^5, S = D G2 / (4 cos theta_i cos theta_o):
  // d f_c / d f0_c = (1 - w) S and d f_c / d alpha = F_c S', S' by a one-variable Jet (Λ and D
  // keep their one definition).
  // The sample's angles depend on the directions alone (Geometry).
  struct Prepared {};
  static Prepared Prepare(const double*) { return {}; }
  using Geometry = HalfAngles<double>;
  static Geometry GeometryOf(const Vec3& wi, const Vec3& wo) { return Angles(wi, wo); }
  static Rgb Value(const double* params, const Prepared&, const Geometry& angles) {
    const double specular = Specular(angles, params[kAlpha]);
    Rgb f;
    for (int c = 0; c < 3; ++c)
      f[c] = SchlickFresnel(angles.cos_theta_d, params[kF0 + c]) * specular;
    return f;
  }
  static void ValueAndGradient(const double* params, const Prepared&, const Geometry& angles,
                               Rgb* f, double gradient[3][2]) {
    using Jet1 = ceres::Jet<double, 1>;
    const Jet1 specular = Specular(angles, Jet1(params[kAlpha], 0));
    const double w = SchlickFresnel(angles.cos_theta_d, 0.0);
    for (int c = 0; c < 3; ++c) {
      const double fresnel = SchlickFresnel(angles.cos_theta_d, params[kF0 + c]);
      (*f)[c] = fresnel * specular.a;
      gradient[c][0] = (1.0 - w) * specular.a;
      gradient[c][1] = fresnel * specular.v[0];
    }
  }

  static LobeCoordinates Lobe(const double* params) {
    return {kHalfVectorFrame, params[kAlpha], &Derived::kLobeDistribution};
  }
  // The lobe's weight in an importance mixture: Schlick's F averaged over the cosine-weighted
  // hemisphere, f0 + (1 - f0) ∫ (1-c)^5 2c dc = f0 + (1 - f0)/21.
  static Rgb LobeWeight(const double* params) {
    const Rgb f0 = LoadRgb(params, kF0);
    return f0 + (1.0 - f0) / 21.0;
  }
  static double EquivalentExponent(const double* params) {
    return Derived::AlphaEquivalentExponent(params[kAlpha]);
  }
  // The largest albedo over incidence per channel, the tabulated bound's.
  template <typename Bound>
  static Rgb MaxAlbedo(const double* params, const Bound& bound) {
    const double log_alpha = std::log(params[kAlpha]);
    Rgb albedo;
    for (int c = 0; c < 3; ++c) albedo[c] = bound.MaxAlbedo(log_alpha, params[kF0 + c]);
    return albedo;
  }

  // The fitter's variables s[1 or 3] and shape[1] (parameterization.h): alpha = exp(shape),
  // f0_c = cap_c logistic(s_c), and the lobe takes M(f0_c) = max_theta E(theta; alpha, f0_c)
  // (`bound`: bound.MaxAlbedo(ln alpha, f0)) of the budget.
  //
  // The first lobe has the whole budget (1) and cap 1: its M(1) is the albedo of a lobe with
  // F = 1, at most 1. A lobe after another one (a clear coat over a base lobe, a lobe after a
  // retro lobe) has what the first left, and its f0 is capped so that it takes no more: M is the
  // largest of E's values at the table's nodes, each linear in f0 (Schlick), so M is convex in f0
  // and M(cap) <= (1 - cap) M(0) + cap M(1), which is the budget for
  //   cap = (budget - M(0)) / (M(1) - M(0))   clamped to [0, 1].
  // The cap cannot go below f0 = 0, and M(0), Schlick's grazing rise, is no small thing for a
  // smooth lobe (0.91 at alpha 0.001, 0.38 at 0.1, 0.03 at 1.5). Where the budget is below it
  // the lobe's roughness is raised until M(0) fits (M(0) falls as alpha grows): the lobe then
  // takes exactly the budget at f0 = 0. A lobe before this one leaves it at least M(0) at the
  // largest alpha (LeastAlbedo; parameterization.h reserves it), so such an alpha always exists.
  static int NumVariables(bool grey) { return (grey ? 1 : 3) + 1; }
  static constexpr bool kFitsAnyBudget = true;  // down to LeastAlbedo (models/term.h)
  // The least albedo the lobe takes anywhere in its variables' range: f0 = 0 at the largest alpha.
  template <typename Bound>
  static double LeastAlbedo(const Bound& bound) {
    return bound.MaxAlbedo(std::log(kFitShapeMax), 0.0);
  }
  // `log_alpha`, or where it leaves the lobe's f0 = 0 albedo above the least of the budget's
  // channels, the smallest log alpha at which that albedo fits: found by bisection on the values,
  // its derivative that of the budget through the slope of M(0) (so the map stays differentiable
  // for the fitter, which then moves alpha by moving what the earlier lobe takes).
  template <typename T, typename Bound>
  static T LogAlphaWithinBudget(const T& log_alpha, const T* budget, const Bound& bound) {
    T least = budget[0];
    for (int c = 1; c < 3; ++c) {
      if (budget[c] < least) least = budget[c];
    }
    if (!(bound.MaxAlbedo(log_alpha, T(0)) > least)) return log_alpha;
    const double target = ValueOf(least);
    double fits = std::log(kFitShapeMax), too_smooth = ValueOf(log_alpha);
    if (bound.MaxAlbedo(fits, 0.0) > target) return T(fits);  // not reserved for: no alpha fits
    for (int step = 0; step < 60; ++step) {
      const double middle = 0.5 * (fits + too_smooth);
      (bound.MaxAlbedo(middle, 0.0) > target ? too_smooth : fits) = middle;
    }
    constexpr double kDelta = 1e-6;
    const double slope =
        (bound.MaxAlbedo(fits + kDelta, 0.0) - bound.MaxAlbedo(fits - kDelta, 0.0)) / (2 * kDelta);
    if (!(slope < 0.0)) return T(fits);
    return T(fits) + (least - T(target)) / T(slope);
  }
  static void VariableBounds(bool grey, double* lower, double* upper) {
    LobeVariableBounds(grey, kFitShapeMin, kFitShapeMax, lower, upper);
  }
  template <typename T, typename Bound>
  static T F0Cap(const T& log_alpha, const T& budget, const Bound& bound) {
    if (!(budget < T(1))) return T(1);
    const T at_zero = bound.MaxAlbedo(log_alpha, T(0));
    const T at_one = bound.MaxAlbedo(log_alpha, T(1));
    if (!(budget > at_zero)) return T(0);
    if (!(at_one > budget)) return T(1);
    return (budget - at_zero) / (at_one - at_zero);
  }
  // The caps of the three channels; a grey lobe (one f0) takes the least of them.
  template <typename T, typename Bound>
  static void F0Caps(const T& log_alpha, const T* budget, bool grey, const Bound& bound, T* caps) {
    for (int c = 0; c < 3; ++c) caps[c] = F0Cap(log_alpha, budget[c], bound);
    if (!grey) return;
    T least = caps[0];
    for (int c = 1; c < 3; ++c) {
      if (caps[c] < least) least = caps[c];
    }
    for (int c = 0; c < 3; ++c) caps[c] = least;
  }
  template <typename T, typename Bound>
  static void Map(const T* variables, bool grey, const T* budget, T* params, T* taken,
                  const Bound& bound) {
    using std::exp;
    const int s = grey ? 1 : 3;
    const T log_alpha = LogAlphaWithinBudget(variables[s], budget, bound);
    T caps[3];
    F0Caps(log_alpha, budget, grey, bound, caps);
    for (int c = 0; c < 3; ++c) {
      const T f0 = caps[c] * Logistic(variables[grey ? 0 : c]);
      params[kF0 + c] = f0;
      taken[c] = bound.MaxAlbedo(log_alpha, f0);
    }
    params[kAlpha] = exp(log_alpha);
  }
  template <typename Bound>
  static void Unmap(const double* params, bool grey, const double* budget, double* variables,
                    double* taken, const Bound& bound) {
    const double log_alpha =
        std::clamp(std::log(params[kAlpha]), std::log(kFitShapeMin), std::log(kFitShapeMax));
    double s[3], caps[3];
    F0Caps(log_alpha, budget, grey, bound, caps);
    for (int c = 0; c < 3; ++c) {
      s[c] = BoundedLogit(caps[c] > 0 ? params[kF0 + c] / caps[c] : 0.0);
      taken[c] = bound.MaxAlbedo(log_alpha, caps[c] * Logistic(s[c]));
    }
    PackShares(s, log_alpha, grey, variables);
  }
  // f0 of the start from the peak (the lobe's own value there with f0 = 0 and f0 = 1, Schlick
  // being linear in f0), or a dielectric's 0.04: the Fresnel rise toward grazing then has to
  // come from the data, which keeps a start from mistaking a grazing peak for a metal.
  template <typename Bound>
  static void Guess(const PeakSample& peak, const TermStart& start, const double*,
                    const Bound& bound, double* variables, double* taken) {
    double unit[kNumParams] = {0, 0, 0, start.shape};
    const double at_zero = Eval<double>(unit, peak.wi, peak.wo)[0];
    for (int k = 0; k < 3; ++k) unit[kF0 + k] = 1.0;
    const double at_one = Eval<double>(unit, peak.wi, peak.wo)[0];
    for (int c = 0; c < 3; ++c) {
      double f0 = 0.04;
      const double excess = peak.value[c] - peak.diffuse[c] - at_zero;
      if (start.from_peak && at_one - at_zero > 1e-12) {
        f0 = std::clamp(excess / (at_one - at_zero), 0.005, 0.95);
      }
      variables[c] = Logit(f0);
      taken[c] = bound.MaxAlbedo(std::log(start.shape), Logistic(variables[c]));
    }
    variables[3] = std::log(start.shape);
  }
  static std::vector<TermStart> Starts(const StartShapes& shapes) {
    std::vector<TermStart> starts;
    for (double alpha : shapes.Of(kShapeScale)) {
      starts.push_back({alpha, true});
      starts.push_back({alpha, false});
    }
    return starts;
  }
};

}  // namespace brdf::models
