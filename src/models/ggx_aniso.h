// ggx-aniso: the GGX microfacet lobe F(wi·h) D(h) G2(wi, wo) / (4 cos theta_i cos theta_o) of a
// surface whose roughness differs along two perpendicular tangent directions: brushed and
// machined metals, hair-line finishes, satin. Heitz, "Understanding the masking-shadowing
// function in microfacet-based BRDFs", JCGT 3(2), 2014, §5.2 and eqs. 79-80, with h and w written
// in the lobe's own tangent frame, x' along alpha_x at azimuth phi0 from the surface's +x:
//   D(h) = 1 / (π α_x α_y (x'²/α_x² + y'²/α_y² + z²)²),
//   Λ(w) = (−1 + sqrt(1 + (α_x² x'² + α_y² y'²) / z²)) / 2,
// the isotropic ggx's Λ (ggx.h) with α² tan²theta replaced by the alphas projected on w's
// azimuth. Fresnel (Schlick) and the height-correlated G2 are the isotropic lobe's
// (microfacet.h); at α_x = α_y the lobe is ggx's, whatever phi0.
//
// The model `ggx-aniso` is lambert+ggx-aniso: f = rho_d/π + the lobe.
// Parameters: f0 (RGB in [0, 1], default 0.04), alpha_x (default 0.2), alpha_y (default 0.1),
// phi0 (radians in [-π, π], default 0: the azimuth of the alpha_x direction). One material has
// several names: (alpha_x, alpha_y, phi0) is (alpha_y, alpha_x, phi0 + π/2), and phi0 is phi0 + π
// (D and Λ are even in x' and y'). A fit reports the canonical one: alpha_x >= alpha_y and phi0
// in [0, π), so that phi0 is the direction of the broader roughness.
// Example: `ggx-aniso:rho_d=0.05:f0=0.9,0.85,0.8:alpha_x=0.3:alpha_y=0.05:phi0=0.5`.
//
// Sampling: the normals visible from wo (Heitz, "Sampling the GGX distribution of visible
// normals", JCGT 7(4), 2018, written for two alphas) are drawn with ggx.h's method in the lobe's
// tangent frame (SampleVisibleNormal, VisibleNormalDensity). The integrators of `brdf energy`
// and the renderer take a lobe through LobeCoordinates (lobe.h), which describe a rotationally
// symmetric lobe by one width: they are handed the isotropic ggx lobe of the geometric-mean
// alpha, which has the same peak height 1/(π α_x α_y). The importance estimators stay unbiased
// (every draw is weighed by the density it was drawn from), only less efficient for an elongated
// lobe; the quadrature integrates each ring of that lobe in panels (ring_panels), since D varies
// along it.
//
// Energy bound: the largest albedo over incidence of the isotropic ggx lobe at the effective alpha
// alpha_y² / alpha_x (alpha_y the smaller; the table of fitters/microfacet_bound.h, shared with
// ggx). The lobe's albedo is E0 + f0 (E1 - E0), Schlick being linear in f0. E1, the albedo with
// F = 1, loses what masking of wi and the facets that send wi below the horizon take, and both
// grow as the slopes stretch from alpha_y to alpha_x along one direction (Λ(w) is at least the
// isotropic Λ at alpha_y), so ggx's at alpha_y bounds it. E0, Schlick's grazing rise alone, is
// not bounded so: grazing along the smoother axis it exceeds ggx's at either alpha (BoundLogAlpha
// gives the numbers), and the smaller effective alpha, at which isotropic ggx's E0 and E1 are
// both larger, covers it. That is a rule checked by sampling, not a proof: tests/ggx_aniso_test.cpp
// checks it over 10,000 random points of the fitter's variables at 90 incidences and 5 azimuths
// each (never exceeded); at alpha_x = alpha_y, where the lobe is ggx's, the bound is ggx's own,
// tight within 1 %. For an elongated lobe it is loose (docs/fitting.md gives the margin).
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/ggx.h"

namespace brdf::models {

struct GgxAnisoLobe {
  static constexpr const char* kName = "ggx-aniso";
  static constexpr const char* kFormula =
      "F D G2 / (4 cos_i cos_o); D = 1/(pi ax ay (x'^2/ax^2 + y'^2/ay^2 + z^2)^2), x' at "
      "azimuth phi0, Schlick F, height-correlated anisotropic Smith G2";
  static constexpr const char* kBoundFormula =
      "max over theta of E_ggx(theta; min(ax, ay)^2 / max(ax, ay), f0)";
  static constexpr const char* kAdds = "anisotropic roughness lowers";
  static constexpr bool kDiffuse = false;
  static constexpr int kF0 = 0;
  static constexpr int kAlphaX = 3;
  static constexpr int kAlphaY = 4;
  static constexpr int kPhi0 = 5;
  static constexpr int kNumParams = 6;
  // alpha_y, the narrower width of a canonical lobe, stands for the lobe's width where one number
  // is asked for (the diagnostics' "sharper than the fit can say", plans).
  static constexpr int kShapeSlot = kAlphaY;
  static constexpr ShapeScale kShapeScale = ShapeScale::kRoughness;
  // The bound is tabulated, in ggx's table (AlbedoTableTerm): no table of its own is built.
  static constexpr bool kTabulatedBound = true;
  using AlbedoTableTerm = GgxLobe;
  // Rows of the parameter table: f0, alpha_x, alpha_y, phi0.
  static constexpr int kGradientSize = 4;
  static constexpr bool kVanishesAtZero = false;  // Schlick's grazing rise, as ggx
  static constexpr double kFitShapeMin = kMinFitRoughness;
  static constexpr double kFitShapeMax = kMaxFitRoughness;

  static std::vector<ParamInfo> Params() {
    return {{"f0", kF0, 3, 0.0, 1.0, 0.04, "Fresnel reflectance at normal incidence (RGB)"},
            {"alpha_x", kAlphaX, 1, GgxLobe::kMinAlpha, GgxLobe::kMaxAlpha, 0.2,
             "roughness along the tangent direction at azimuth phi0"},
            {"alpha_y", kAlphaY, 1, GgxLobe::kMinAlpha, GgxLobe::kMaxAlpha, 0.1,
             "roughness across it (at azimuth phi0 + 90 deg)"},
            {"phi0", kPhi0, 1, -kPi, kPi, 0.0,
             "azimuth of the alpha_x direction from the surface's +x, radians"}};
  }

  // ---- evaluation -----------------------------------------------------------------------------

  // The lobe's tangent frame: the alphas and the direction of alpha_x.
  template <typename T>
  struct Shape {
    T alpha_x, alpha_y, cos_phi0, sin_phi0;
  };
  template <typename T>
  static Shape<T> ShapeOf(const T* params) {
    using std::cos;
    using std::sin;
    return {params[kAlphaX], params[kAlphaY], cos(params[kPhi0]), sin(params[kPhi0])};
  }
  // x' and y' of w in the lobe's frame.
  template <typename T, typename D>
  static void TangentCoordinates(const Shape<T>& shape, const Vec3T<D>& w, T* x, T* y) {
    *x = shape.cos_phi0 * T(w.x()) + shape.sin_phi0 * T(w.y());
    *y = shape.cos_phi0 * T(w.y()) - shape.sin_phi0 * T(w.x());
  }
  template <typename T, typename D>
  static T Distribution(const Shape<T>& shape, const Vec3T<D>& h) {
    T x, y;
    TangentCoordinates(shape, h, &x, &y);
    const T x_scaled = x / shape.alpha_x, y_scaled = y / shape.alpha_y;
    const T sum = x_scaled * x_scaled + y_scaled * y_scaled + T(h.z() * h.z());
    return T(1) / (T(kPi) * shape.alpha_x * shape.alpha_y * sum * sum);
  }
  template <typename T, typename D>
  static T Lambda(const Shape<T>& shape, const Vec3T<D>& w) {
    T x, y;
    TangentCoordinates(shape, w, &x, &y);
    const T projected =
        x * x * shape.alpha_x * shape.alpha_x + y * y * shape.alpha_y * shape.alpha_y;
    return GgxLobe::LambdaOfRoughSlope(projected / T(w.z() * w.z()));
  }

  // What a sample's f takes of its directions: both directions, the half vector and Fresnel's
  // angle (the lobe's frame turns with phi0, a parameter, so nothing of it is computed here).
  struct Geometry {
    Vec3 wi, wo, half_vector;
    double cos_theta_d = 0;
  };
  template <typename D>
  static Geometry GeometryOf(const Vec3T<D>& wi, const Vec3T<D>& wo) {
    using std::sqrt;
    const Vec3T<D> sum = wi + wo;
    const Vec3T<D> half_vector = sum / D(sqrt(sum.squaredNorm()));
    return {wi.template cast<double>(), wo.template cast<double>(),
            half_vector.template cast<double>(), double(wi.dot(half_vector))};
  }
  // D G2 / (4 cos theta_i cos theta_o), for wi and wo above the horizon.
  template <typename T, typename D>
  static T Specular(const Shape<T>& shape, const Vec3T<D>& wi, const Vec3T<D>& wo,
                    const Vec3T<D>& half_vector) {
    // Height-correlated Smith G2 (Heitz 2014, eq. 99), with the anisotropic Λ.
    const T masking = T(1) / (T(1) + Lambda(shape, wi) + Lambda(shape, wo));
    return Distribution(shape, half_vector) * masking / T(4 * wi.z() * wo.z());
  }

  // The part and the colour are ggx's (microfacet.h): f_c = F(f0_c, theta_d) times the part.
  template <typename T>
  using Part = GgxLobe::Part<T>;
  template <typename T, typename D>
  static Part<T> Angular(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    using std::sqrt;
    const Vec3T<D> sum = wi + wo;
    const Vec3T<D> half_vector = sum / D(sqrt(sum.squaredNorm()));
    return {Specular(ShapeOf(params), wi, wo, half_vector), T(wi.dot(half_vector))};
  }
  template <typename T>
  static RgbT<T> Colour(const T* params, const Part<T>& part) {
    return GgxLobe::Colour(params, part);
  }
  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    return Colour(params, Angular<T, D>(params, wi, wo));
  }

  // d f_c / d f0_c = (1 - w) S as ggx's; d f_c / d (alpha_x, alpha_y, phi0) = F_c dS, dS by a
  // three-variable Jet of Specular (one definition), its frame prepared once per point.
  using Jet3 = ceres::Jet<double, 3>;
  using Prepared = Shape<Jet3>;
  static Prepared Prepare(const double* params) {
    const Jet3 variables[kNumParams] = {Jet3(0),
                                        Jet3(0),
                                        Jet3(0),
                                        Jet3(params[kAlphaX], 0),
                                        Jet3(params[kAlphaY], 1),
                                        Jet3(params[kPhi0], 2)};
    return ShapeOf(variables);
  }
  static Rgb Value(const double* params, const Prepared& prepared, const Geometry& geometry) {
    const Shape<double> shape{prepared.alpha_x.a, prepared.alpha_y.a, prepared.cos_phi0.a,
                              prepared.sin_phi0.a};
    const double specular = Specular(shape, geometry.wi, geometry.wo, geometry.half_vector);
    return GgxLobe::Colour(params, Part<double>{specular, geometry.cos_theta_d});
  }
  static void ValueAndGradient(const double* params, const Prepared& prepared,
                               const Geometry& geometry, Rgb* f, double gradient[3][4]) {
    const Jet3 specular = Specular(prepared, geometry.wi, geometry.wo, geometry.half_vector);
    const double w = SchlickFresnel(geometry.cos_theta_d, 0.0);
    for (int c = 0; c < 3; ++c) {
      const double fresnel = SchlickFresnel(geometry.cos_theta_d, params[kF0 + c]);
      (*f)[c] = fresnel * specular.a;
      gradient[c][0] = (1.0 - w) * specular.a;
      for (int k = 0; k < 3; ++k) gradient[c][1 + k] = fresnel * specular.v[k];
    }
  }

  // ---- sampling -------------------------------------------------------------------------------

  // A half vector drawn from the normals visible from wo (Heitz 2018), D_wo(h) = G1(wo) max(0,
  // wo.h) D(h) / cos theta_o: ggx.h's draw with the two alphas in the lobe's frame, turned back.
  static Vec3 SampleVisibleNormal(const double* params, const Vec3& wo, double u0, double u1) {
    const Shape<double> shape = ShapeOf(params);
    double x, y;
    TangentCoordinates(shape, wo, &x, &y);
    const Vec3 local = GgxLobe::SampleVisibleNormal(
        GgxLobe::VisibleNormalFrameOf(Vec3(x, y, wo.z()), shape.alpha_x, shape.alpha_y), u0, u1);
    return Vec3(shape.cos_phi0 * local.x() - shape.sin_phi0 * local.y(),
                shape.sin_phi0 * local.x() + shape.cos_phi0 * local.y(), local.z());
  }
  // Its density in solid angle of h.
  static double VisibleNormalDensity(const double* params, const Vec3& wo, const Vec3& h) {
    const double wo_dot_h = wo.dot(h);
    if (!(wo.z() > 0.0) || !(h.z() > 0.0) || !(wo_dot_h > 0.0)) return 0.0;
    const Shape<double> shape = ShapeOf(params);
    return Distribution(shape, h) * wo_dot_h / ((1.0 + Lambda(shape, wo)) * wo.z());
  }

  // ---- what the integrators, the renderer and the bound take ----------------------------------

  // The isotropic ggx lobe of the geometric-mean alpha (see above).
  // Its rings of constant theta_h carry D's variation with the azimuth, a peak about as wide as
  // the ratio of the alphas: the quadrature's azimuthal rule gets 8 panels per unit of the ratio
  // (the tests check the albedo against the visible normals' integral to 2e-4 up to a ratio of
  // 10), at most kMaxRingPanels. Without the cap a fit that ran to the alphas' bounds (1.5 and
  // 0.001, a ratio of 1500, on hostile data) spent 330 s in its energy check; beyond a ratio of
  // 32 the rings' own error estimate, part of the albedo's stated error, says what the cap costs.
  static constexpr int kMaxRingPanels = 256;
  static LobeCoordinates Lobe(const double* params) {
    const double ratio =
        std::max(params[kAlphaX], params[kAlphaY]) / std::min(params[kAlphaX], params[kAlphaY]);
    LobeCoordinates lobe{kHalfVectorFrame, std::sqrt(params[kAlphaX] * params[kAlphaY]),
                         &GgxLobe::kLobeDistribution};
    lobe.ring_panels =
        ratio > 1.0 ? static_cast<int>(std::min<double>(std::ceil(8.0 * ratio), kMaxRingPanels))
                    : 1;
    return lobe;
  }
  static Rgb LobeWeight(const double* params) { return GgxLobe::LobeWeight(params); }
  static double EquivalentExponent(const double* params) {
    return GgxLobe::AlphaEquivalentExponent(std::sqrt(params[kAlphaX] * params[kAlphaY]));
  }
  // The alpha whose isotropic ggx table bounds the lobe: alpha_y² / alpha_x (= alpha at
  // isotropy), in log, within the table's range. The smaller alpha alone bounds the part with F =
  // 1 (masking only grows as the slopes stretch) but not Schlick's grazing rise at f0 = 0: at
  // alphas 1.05 and 0.68, grazing along the smoother axis, it reaches 0.074 where isotropic ggx
  // reaches 0.060 at 0.68 and 0.038 at 1.05 (and 0.099 at 0.68² / 1.05 = 0.44). The isotropic
  // lobe's E0 and E1 both grow as alpha falls, so the smaller effective alpha covers both.
  template <typename T>
  static T BoundLogAlpha(const T& log_alpha_x, const T& log_alpha_y) {
    return ClampLogAlpha(T(T(2) * log_alpha_y - log_alpha_x));
  }
  // The largest albedo over incidence per channel: isotropic ggx's at BoundLogAlpha.
  template <typename Bound>
  static Rgb MaxAlbedo(const double* params, const Bound& bound) {
    const double log_x = std::log(params[kAlphaX]), log_y = std::log(params[kAlphaY]);
    const double log_alpha = BoundLogAlpha(std::max(log_x, log_y), std::min(log_x, log_y));
    Rgb albedo;
    for (int c = 0; c < 3; ++c) albedo[c] = bound.MaxAlbedo(log_alpha, params[kF0 + c]);
    return albedo;
  }

  // ---- the fitter's variables -----------------------------------------------------------------
  //
  // s[1 or 3], then a, b and m: f0_c = cap_c logistic(s_c) as ggx's (microfacet.h, the cap from
  // the bound at BoundLogAlpha), m = ln sqrt(alpha_x alpha_y) (ggx's log alpha, so ggx's
  // starts and guess serve), and (a, b) = r (cos 2 phi0, sin 2 phi0) with r = ln sqrt(alpha_x /
  // alpha_y) >= 0: the deviatoric part of the log of the slope tensor, so that
  //   alpha_x = exp(m + r), alpha_y = exp(m - r), phi0 = atan2(b, a) / 2 in [0, π).
  // Every point of the variables is one material named canonically (alpha_x >= alpha_y), and f is
  // a smooth function of (a, b) through the isotropic point a = b = 0, where the direction is
  // undefined: near it, the fit's gradient points toward the data's direction of anisotropy
  // whatever it is, where a start along any one fixed direction (phi0 = 0) would sit on a saddle
  // for data symmetric about the diagonal. (The energy bound is not smooth there: it depends on
  // r = |(a, b)|, and through the budget so does rho_d.) Only the point a = b = 0 has no derivative
  // (phi0 there is undefined): starts and the inverse map sit a hair away from it
  // (kStartAnisotropy), and the fit does not land on it by chance. Each alpha stays within the
  // fitter's range of microfacet roughness, that of the tabulated bound (a box on (m, a, b)
  // cannot say so: m ± r is clamped to it, which stops that alpha there).
  static constexpr double kMaxLogAnisotropy = 4.0;  // beyond ln(1.5 / 1e-3) / 2: the clamps bind
  static constexpr double kStartAnisotropy = 1e-6;  // r of an isotropic start
  static constexpr int Shares(bool grey) { return grey ? 1 : 3; }
  static int NumVariables(bool grey) { return Shares(grey) + 3; }
  // Its Map caps f0 by the budget but does not raise the alphas to fit a budget below its f0 = 0
  // albedo, as MicrofacetLobe::LogAlphaWithinBudget does: it can only be the first lobe, whose
  // budget always holds that albedo (parameterization.h refuses it anywhere else at compile time).
  static constexpr bool kFitsAnyBudget = false;
  static void VariableBounds(bool grey, double* lower, double* upper) {
    const int s = Shares(grey);
    LobeVariableBounds(grey, kFitShapeMin, kFitShapeMax, lower, upper);  // shares, then m
    lower[s + 2] = lower[s];  // m last: a term's shape variable is its last (parameterization.h)
    upper[s + 2] = upper[s];
    for (int k = s; k < s + 2; ++k) {
      lower[k] = -kMaxLogAnisotropy;
      upper[k] = kMaxLogAnisotropy;
    }
  }
  template <typename T>
  static T ClampLogAlpha(const T& log_alpha) {
    const double log_min = std::log(kFitShapeMin), log_max = std::log(kFitShapeMax);
    if (log_alpha < T(log_min)) return T(log_min);
    if (log_alpha > T(log_max)) return T(log_max);
    return log_alpha;
  }
  template <typename T, typename Bound>
  static void Map(const T* variables, bool grey, const T* budget, T* params, T* taken,
                  const Bound& bound) {
    using std::atan2;
    using std::exp;
    using std::sqrt;
    const int s = Shares(grey);
    const T& a = variables[s];
    const T& b = variables[s + 1];
    const T& m = variables[s + 2];
    T r(0), phi0(0);
    if (a != T(0) || b != T(0)) {
      r = sqrt(a * a + b * b);
      phi0 = T(0.5) * atan2(b, a);
      if (phi0 < T(0)) phi0 += T(kPi);  // atan2 in (-π, π]: phi0 in [0, π)
    }
    const T log_alpha_x = ClampLogAlpha(T(m + r)), log_alpha_y = ClampLogAlpha(T(m - r));
    const T log_alpha_bound = BoundLogAlpha(log_alpha_x, log_alpha_y);
    T caps[3];
    GgxLobe::F0Caps(log_alpha_bound, budget, grey, bound, caps);
    for (int c = 0; c < 3; ++c) {
      const T f0 = caps[c] * Logistic(variables[grey ? 0 : c]);
      params[kF0 + c] = f0;
      taken[c] = bound.MaxAlbedo(log_alpha_bound, f0);
    }
    params[kAlphaX] = exp(log_alpha_x);
    params[kAlphaY] = exp(log_alpha_y);
    params[kPhi0] = phi0;
  }
  // Any name of the material: r takes the sign of ln(alpha_x / alpha_y), and a negative r along
  // phi0 is the positive one along phi0 + π/2, which (a, b) say alike.
  template <typename Bound>
  static void Unmap(const double* params, bool grey, const double* budget, double* variables,
                    double* taken, const Bound& bound) {
    const int s = Shares(grey);
    const double log_x = ClampLogAlpha(std::log(params[kAlphaX]));
    const double log_y = ClampLogAlpha(std::log(params[kAlphaY]));
    double r = 0.5 * (log_x - log_y);
    if (std::abs(r) < kStartAnisotropy) r = kStartAnisotropy;
    const double log_alpha_bound = BoundLogAlpha(std::max(log_x, log_y), std::min(log_x, log_y));
    double shares[3], caps[3];
    GgxLobe::F0Caps(log_alpha_bound, budget, grey, bound, caps);
    for (int c = 0; c < 3; ++c) {
      shares[c] = BoundedLogit(caps[c] > 0 ? params[kF0 + c] / caps[c] : 0.0);
      taken[c] = bound.MaxAlbedo(log_alpha_bound, caps[c] * Logistic(shares[c]));
    }
    PackShares(shares, 0.0, grey, variables);
    variables[s] =
        std::clamp(r * std::cos(2 * params[kPhi0]), -kMaxLogAnisotropy, kMaxLogAnisotropy);
    variables[s + 1] =
        std::clamp(r * std::sin(2 * params[kPhi0]), -kMaxLogAnisotropy, kMaxLogAnisotropy);
    variables[s + 2] = 0.5 * (log_x + log_y);
  }
  // ggx's start (f0 from the peak, m its log alpha), isotropic: (a, b) a hair from 0 (above).
  // The variables in the three-channel layout: s[3], a, b, m.
  template <typename Bound>
  static void Guess(const PeakSample& peak, const TermStart& start, const double* budget,
                    const Bound& bound, double* variables, double* taken) {
    GgxLobe::Guess(peak, start, budget, bound, variables, taken);
    variables[5] = variables[3];
    variables[3] = kStartAnisotropy;
    variables[4] = 0.0;
  }
  static std::vector<TermStart> Starts(const StartShapes& shapes) {
    return GgxLobe::Starts(shapes);
  }
};

}  // namespace brdf::models
