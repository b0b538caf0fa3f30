// What every term of a reflectance model provides (DESIGN §2, "Composition"). A model is a
// composition (composition.h): one diffuse term plus zero, one or two lobes, and f is their sum.
// A term is one struct in one header of this folder and one entry of model_list.h; nothing
// outside this folder asks what kind of term it is, it asks the term.
//
// A term T provides (p: the term's own parameters, slots from 0; f in sr^-1, no cosine):
//   kName, kFormula              as written in model strings and reports
//   kDiffuse                     true for a diffuse term (first in a composition), else a lobe
//   kNumParams, Params()         its parameter table (ParamInfo, slots local to the term)
//   Eval<T, D>(p, wi, wo)        its f, zero below the horizon (one definition for double, float
//                                and ceres::Jet; D the directions' scalar)
// The fast loops (the fitter's analytic Jacobian, the renderer's float batches) take the term in
// two steps, for wi and wo above the horizon:
//   Part<T>, Angular<T, D>(p, wi, wo) -> Part<T>   what depends on the directions (and on the
//                                                   shape parameter), one vectorizable loop
//   Colour<T>(p, part) -> RgbT<T>                  the term's f from it, per channel
//   Prepared, Prepare(p)          what every sample shares at one point of the parameters
//   Geometry, GeometryOf(wi, wo)  what a sample's f takes of its directions, computed once a fit
//   Value(p, prepared, geometry)  f, and ValueAndGradient(p, prepared, geometry, f, grad): f and
//                                d f_c / d (the table's parameters in order, channel c of an RGB
//                                one) per channel, in closed form
// For the integrators and samplers (a lobe; a diffuse term answers with the normal):
//   Lobe(p) -> LobeCoordinates, LobeWeight(p) -> Rgb, EquivalentExponent(p)
// For the energy bound and the fitter's free variables (fitters/parameterization.h):
//   kShapeSlot (-1 without one), kFitShapeMin/Max, kShapeScale
//   NumVariables(grey), Map<T>(vars, grey, budget, params, bound) -> the albedo it takes from the
//   budget (never more: every reachable point conserves energy), Unmap (its inverse), Starts,
//   Guess; for a lobe, kFitsAnyBudget: whether its Map keeps within any budget down to its
//   LeastAlbedo(bound), the least it takes anywhere in its variables' range (a microfacet lobe's
//   f0 = 0 albedo at its largest alpha), which the lobes before it leave it. Only such a lobe may
//   follow another, and only it provides LeastAlbedo.
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/common.h"

namespace brdf::models {

// What a lobe's shape parameter measures, so that the fitter hands it the start values of the
// same kind (FitOptions::start_exponents or start_alphas).
enum class ShapeScale { kNone, kExponent, kRoughness };

// One start of the multi-start for a lobe: its shape, and whether the lobe's per-channel
// parameter is read from the data's peak (else a fixed guess, e.g. a dielectric's f0 = 0.04).
struct TermStart {
  double shape = 1.0;
  bool from_peak = true;
};

// The range a fit gives a shape of each scale: exponents up to 1e6 cover real materials
// (measured lobes reach ~1e5) with room to spare; a roughness from a near-mirror to beyond matte
// (the range of the fitter's tabulated microfacet bound, fitters/microfacet_bound.h).
inline constexpr double kMinFitExponent = 1.0, kMaxFitExponent = 1e6;
inline constexpr double kMinFitRoughness = 1e-3, kMaxFitRoughness = 1.5;

// The start values a lobe's shape takes, by its scale.
struct StartShapes {
  std::vector<double> exponents, roughnesses;
  const std::vector<double>& Of(ShapeScale scale) const {
    return scale == ShapeScale::kRoughness ? roughnesses : exponents;
  }
};

// What a lobe's Guess reads of the data: the brightest sample (by its largest channel), each
// channel's largest value, and the diffuse floor's guess.
struct PeakSample {
  Vec3 wi, wo;
  Rgb value = Rgb::Zero();        // of the brightest sample
  Rgb channel_max = Rgb::Zero();  // over every sample
  Rgb diffuse = Rgb::Zero();      // rho_d / pi of the start
};

// The inverse of a logistic map kept inside the fitter's box (+-kLogisticBound): a parameter at
// its bound maps to a saturated variable.
inline constexpr double kLogisticBound = 40.0;  // logistic(-40) = 4e-18: "zero" is reachable

// The value of a scalar of the templated code: a double itself, a Jet's value part (for choices
// made on values, such as a bisection, whose derivative is then put back by hand).
inline double ValueOf(double x) { return x; }
template <typename T, int N>
double ValueOf(const ceres::Jet<T, N>& x) {
  return ValueOf(x.a);
}

template <typename T>
T Logistic(const T& x) {
  using std::exp;
  return T(1) / (T(1) + exp(-x));
}
inline double Logit(double p) { return std::log(p / (1.0 - p)); }
inline double BoundedLogit(double p) {
  if (!(p > 0)) return -kLogisticBound;
  if (!(p < 1)) return kLogisticBound;
  return std::clamp(Logit(p), -kLogisticBound, kLogisticBound);
}

// The box of a lobe's variables: its shares (one, or one per channel) within +-kLogisticBound,
// then the log of its shape within [shape_min, shape_max].
inline void LobeVariableBounds(bool grey, double shape_min, double shape_max, double* lower,
                               double* upper) {
  const int shares = grey ? 1 : 3;
  std::fill(lower, lower + shares, -kLogisticBound);
  std::fill(upper, upper + shares, kLogisticBound);
  lower[shares] = std::log(shape_min);
  upper[shares] = std::log(shape_max);
}

// A lobe's variables from the three-channel layout of its Guess (s[3], then `count` - 3 more):
// for a grey lobe the shares' mean, then the rest.
inline void PackVariables(const double* three_channel, int count, bool grey, double* variables) {
  const int shares = grey ? 1 : 3;
  if (grey) {
    variables[0] = (three_channel[0] + three_channel[1] + three_channel[2]) / 3.0;
  } else {
    for (int c = 0; c < 3; ++c) variables[c] = three_channel[c];
  }
  for (int k = 3; k < count; ++k) variables[shares + k - 3] = three_channel[k];
}

// A lobe's variables from its per-channel shares s[3] and its shape: s[0..2] then the shape, or
// for a grey lobe (one share for all channels) their mean, then the shape.
inline void PackShares(const double* s, double shape, bool grey, double* variables) {
  if (grey) {
    variables[0] = (s[0] + s[1] + s[2]) / 3.0;
    variables[1] = shape;
  } else {
    for (int c = 0; c < 3; ++c) variables[c] = s[c];
    variables[3] = shape;
  }
}

}  // namespace brdf::models
