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
// Parameters: f0 (RGB in [0, 1], default 0.04), alpha_x (default 0.1), alpha_y (default 0.2),
// phi0 (radians in [-π, π], default 0: the azimuth of the alpha_x direction). One material has
// two names: (alpha_x, alpha_y, phi0) and (alpha_y, alpha_x, phi0 + π/2); and phi0 and phi0 + π
// are the same (D and Λ are even in x' and y'). A fit reports phi0 in [0, π) and either order.
// Example: `ggx-aniso:rho_d=0.05:f0=0.9,0.85,0.8:alpha_x=0.05:alpha_y=0.3:phi0=0.5`.
//
// Sampling: Heitz, "Sampling the GGX distribution of visible normals", JCGT 7(4), 2018, is
// written for two alphas; the sampler here draws with ggx.h's, in the lobe's tangent frame.
// The integrators of `brdf energy` and the renderer take the lobe's coordinates, which describe a
// rotationally symmetric lobe (lobe.h): they are handed the isotropic ggx lobe of the geometric
// mean alpha, which has the same peak height 1/(π α_x α_y). The estimators stay unbiased (every
// draw is weighed by the density it was drawn from), only less efficient for a very elongated
// lobe.
//
// Energy bound: max over theta of the isotropic ggx lobe's albedo at the smaller alpha (the
// table of fitters/microfacet_bound.h, shared with ggx). Why it bounds: the albedo of a
// single-scattering microfacet lobe, ∫ F G2/G1(wo) over the visible normals, loses what the
// masking of wi and the facets that send wi below the horizon take, and both grow with the
// surface's slopes. Stretching the surface's slopes along any tangent direction (alpha_min to
// alpha_max along y') only steepens it: its slope distribution along every azimuth is at least
// as wide, Λ(w) >= the isotropic Λ at alpha_min for every w, and its albedo at every (theta,
// phi) is at most the isotropic surface's at the same theta. That is an argument, not a proof:
// the tests check it (composition_terms_test.cpp: 10,000 random parameter points at 90
// incidences and 8 azimuths each, never exceeded; within 1 % at alpha_x = alpha_y, where the
// lobe is ggx's and the bound is ggx's own). The bound is loose for an elongated lobe (docs:
// models.md gives the margin against the anisotropy ratio), which costs a fit nothing as long
// as the material is far from the budget.
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
  static constexpr const char* kBoundFormula = "max over theta of E_ggx(theta; min(ax, ay), f0)";
  static constexpr const char* kAdds = "anisotropic roughness lowers";
  static constexpr bool kDiffuse = false;
  static constexpr int kF0 = 0;
  static constexpr int kAlphaX = 3;
  static constexpr int kAlphaY = 4;
  static constexpr int kPhi0 = 5;
  static constexpr int kNumParams = 6;
  // alpha_x stands for the lobe's width where one number is asked for (diagnostics, plans).
  static constexpr int kShapeSlot = kAlphaX;
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
    return {
        {"f0", kF0, 3, 0.0, 1.0, 0.04, "Fresnel reflectance at normal incidence (RGB)"},
        {"alpha_x", kAlphaX, 1, GgxLobe::kMinAlpha, GgxLobe::kMaxAlpha, 0.1,
         "roughness along the tangent direction at azimuth phi0"},
        {"alpha_y", kAlphaY, 1, GgxLobe::kMinAlpha, GgxLobe::kMaxAlpha, 0.2,
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
    const T projected = x * x * shape.alpha_x * shape.alpha_x + y * y * shape.alpha_y * shape.alpha_y;
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
  static LobeCoordinates Lobe(const double* params) {
    return {LobeFrame::kHalfVector, std::sqrt(params[kAlphaX] * params[kAlphaY]),
            &GgxLobe::kLobeDistribution};
  }
  static Rgb LobeWeight(const double* params) { return GgxLobe::LobeWeight(params); }
  static double EquivalentExponent(const double* params) {
    return GgxLobe::AlphaEquivalentExponent(std::sqrt(params[kAlphaX] * params[kAlphaY]));
  }
  // The largest albedo over incidence per channel is at most ggx's at the smaller alpha.
  template <typename Bound>
  static Rgb MaxAlbedo(const double* params, const Bound& bound) {
    const double log_alpha = std::log(std::min(params[kAlphaX], params[kAlphaY]));
    Rgb albedo;
    for (int c = 0; c < 3; ++c) albedo[c] = bound.MaxAlbedo(log_alpha, params[kF0 + c]);
    return albedo;
  }

  // ---- the fitter's variables -----------------------------------------------------------------
  //
  // s[1 or 3], then m, r and t: f0_c = cap_c logistic(s_c) as ggx's (microfacet.h, the cap from
  // the bound at the smaller alpha), alpha_x = exp(m + r), alpha_y = exp(m - r), phi0 = t
  // brought into [0, π). m is ggx's log alpha (the geometric mean), so ggx's starts and guess
  // serve: a start is the isotropic lobe (r = 0, t = 0), and the fit turns t once r departs
  // from 0. The boxes keep the alphas within the parameter table's range: the mean within
  // [1e-3, 0.8], their ratio within e^±3 (20).
  static constexpr double kMaxLogMean = -0.22314355131420976;  // ln 0.8
  static constexpr double kMaxLogRatio = 1.5;                  // r: alpha_x / alpha_y = e^(2r)
  static int NumVariables(bool grey) { return (grey ? 1 : 3) + 3; }
  static void VariableBounds(bool grey, double* lower, double* upper) {
    const int s = grey ? 1 : 3;
    LobeVariableBounds(grey, kFitShapeMin, std::exp(kMaxLogMean), lower, upper);
    lower[s + 1] = -kMaxLogRatio;
    upper[s + 1] = kMaxLogRatio;
    lower[s + 2] = -kLogisticBound;  // the angle wraps: its box only keeps it finite
    upper[s + 2] = kLogisticBound;
  }
  template <typename T, typename Bound>
  static void Map(const T* variables, bool grey, const T* budget, T* params, T* taken,
                  const Bound& bound) {
    using std::exp;
    const int s = grey ? 1 : 3;
    const T& m = variables[s];
    const T& r = variables[s + 1];
    const T log_alpha_min = r < T(0) ? m + r : m - r;
    T caps[3];
    GgxLobe::F0Caps(log_alpha_min, budget, grey, bound, caps);
    for (int c = 0; c < 3; ++c) {
      const T f0 = caps[c] * Logistic(variables[grey ? 0 : c]);
      params[kF0 + c] = f0;
      taken[c] = bound.MaxAlbedo(log_alpha_min, f0);
    }
    params[kAlphaX] = exp(m + r);
    params[kAlphaY] = exp(m - r);
    // The box bounds t to +-40: a dozen turns of π at most.
    T phi0 = variables[s + 2];
    while (phi0 < T(0)) phi0 += T(kPi);
    while (!(phi0 < T(kPi))) phi0 -= T(kPi);
    params[kPhi0] = phi0;
  }
  template <typename Bound>
  static void Unmap(const double* params, bool grey, const double* budget, double* variables,
                    double* taken, const Bound& bound) {
    const int s = grey ? 1 : 3;
    const double log_x = std::log(params[kAlphaX]), log_y = std::log(params[kAlphaY]);
    const double m = std::clamp(0.5 * (log_x + log_y), std::log(kFitShapeMin), kMaxLogMean);
    const double r = std::clamp(0.5 * (log_x - log_y), -kMaxLogRatio, kMaxLogRatio);
    const double log_alpha_min = m - std::abs(r);
    double shares[3], caps[3];
    GgxLobe::F0Caps(log_alpha_min, budget, grey, bound, caps);
    for (int c = 0; c < 3; ++c) {
      shares[c] = BoundedLogit(caps[c] > 0 ? params[kF0 + c] / caps[c] : 0.0);
      taken[c] = bound.MaxAlbedo(log_alpha_min, caps[c] * Logistic(shares[c]));
    }
    PackShares(shares, m, grey, variables);
    variables[s + 1] = r;
    variables[s + 2] = params[kPhi0];
  }
  // ggx's: f0 from the peak at the isotropic start; r and t stay 0.
  template <typename Bound>
  static void Guess(const PeakSample& peak, const TermStart& start, const double* budget,
                    const Bound& bound, double* variables, double* taken) {
    GgxLobe::Guess(peak, start, budget, bound, variables, taken);
  }
  static std::vector<TermStart> Starts(const StartShapes& shapes) {
    return GgxLobe::Starts(shapes);
  }
};

}  // namespace brdf::models
