// The energy bound of the microfacet models (DESIGN §2, §6). rho_d/π is summed with the lobe
// without coupling, so the directional albedo is a(theta) = rho_d + E(theta; alpha, f0), and
// with Fresnel the lobe's albedo E peaks toward grazing, not at normal incidence. The bound a
// fit must respect is therefore
//   rho_d + max over theta of E(theta; alpha, f0) <= 1   (per channel).
//
// Schlick's F is linear in f0, so E is too: E = (1 - f0) E_0(theta, alpha) + f0 E_1(theta, alpha),
// with E_0 the albedo of the lobe with f0 = 0 (only Schlick's (1 - cos)^5 rise) and E_1 with
// f0 = 1 (F = 1). The two are tabulated (Kulla & Conty, "Revisiting physically based shading at
// Imageworks", SIGGRAPH 2017 course, tabulate the same directional albedo) by the energy
// library's lobe quadrature of the model's own Eval (energy/lobe_quadrature.h, tolerance 1e-7) —
// nothing is typed in by hand. The build does it once: `brdf_albedo_tables` (albedo_tables.cpp)
// integrates every microfacet model of the list and writes the values, exactly, into a source
// file compiled into this library, so that a fit does not spend seconds of CPU on it in every
// process; a model without a built table is integrated at its first use. The nodes:
//   * alpha on 40 nodes, uniform in ln(alpha) over the fitter's range [1e-3, 1.5];
//   * theta on 60 nodes 1.5 deg apart from 0 to 88.5 deg, and 24 nodes at alpha tan(theta) =
//     0.3 ... 3000 (log-spaced), the scale on which Smith's Λ changes (it depends on nothing
//     else). The maximum lies there: as theta_o -> 90 deg the visible facets tilt toward wo and
//     reflect it upward, so the height-correlated G2 / G1(wo) -> 1 and E tends to the Fresnel-
//     weighted share of such facets (for F = 1, to nearly 1) — the lobe is brightest at grazing.
// max over theta is taken over the nodes of each channel's f0, each node's E interpolated in
// ln(alpha) by Catmull-Rom; the result is raised by a margin (0.2 % of E plus 2e-4) that covers
// the interpolation, the maximum falling between theta nodes and the quadrature's error, all of
// which are below 1e-4 by the tests (microfacet_bound_test), so the fitted material's true
// maximum stays <= 1 while the bound stays within 1 % of it.
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "models/registry.h"
#include "models/term.h"

namespace brdf::fitters {

using models::ValueOf;

class MicrofacetAlbedoTable {
 public:
  static constexpr double kMinAlpha = models::kMinFitRoughness;
  static constexpr double kMaxAlpha = models::kMaxFitRoughness;
  static constexpr int kAlphaNodes = 40;
  static constexpr int kUniformThetaNodes = 60;
  static constexpr double kUniformThetaStepDeg = 1.5;
  static constexpr int kGrazingThetaNodes = 24;
  static constexpr double kMinGrazingScale = 0.3, kMaxGrazingScale = 3000.0;
  static constexpr double kRelativeMargin = 2e-3, kAbsoluteMargin = 2e-4;

  // Integrates the lobe of `info` (a microfacet model) at every node; parallel (TBB).
  explicit MicrofacetAlbedoTable(const ModelInfo& info);
  // The table of values integrated before (NodeCount() each, node j * ThetaNodes() + k).
  MicrofacetAlbedoTable(std::vector<double> e0, std::vector<double> e1)
      : e0_(std::move(e0)), e1_(std::move(e1)) {}

  // The lobe albedo at node (j, k) of `info` for f0 = 0 and f0 = 1, integrated now.
  static std::pair<double, double> IntegrateNode(const ModelInfo& info, int j, int k);
  static int NodeCount() { return kAlphaNodes * ThetaNodes(); }

  // Incidence angle of theta node k at alpha node j, radians.
  static double NodeTheta(int k, double alpha);
  static int ThetaNodes() { return kUniformThetaNodes + kGrazingThetaNodes; }
  static double NodeAlpha(int j);

  // Tabulated lobe albedo at node (j, k) for f0 = 0 and f0 = 1.
  double E0(int j, int k) const { return e0_[j * ThetaNodes() + k]; }
  double E1(int j, int k) const { return e1_[j * ThetaNodes() + k]; }

  // max over theta of E(theta; alpha, f0) with the margin: the bound. `log_alpha` within
  // [ln kMinAlpha, ln kMaxAlpha] (clamped), f0 in [0, 1]. Templated for Ceres Jets: the
  // maximising node is chosen on the values, the derivative is that node's.
  template <typename T>
  T MaxLobeAlbedo(const T& log_alpha, const T& f0) const {
    int j;
    const T t = AlphaCell(log_alpha, &j);
    const double t_value = ValueOf(t), f0_value = ValueOf(f0);
    int best = 0;
    double best_value = -1;
    for (int k = 0; k < ThetaNodes(); ++k) {
      const double e0 = Interpolate(&MicrofacetAlbedoTable::E0, j, k, t_value);
      const double e1 = Interpolate(&MicrofacetAlbedoTable::E1, j, k, t_value);
      const double value = e0 + f0_value * (e1 - e0);
      if (value > best_value) {
        best_value = value;
        best = k;
      }
    }
    const T e0 = Interpolate(&MicrofacetAlbedoTable::E0, j, best, t);
    const T e1 = Interpolate(&MicrofacetAlbedoTable::E1, j, best, t);
    return (e0 + f0 * (e1 - e0)) * T(1 + kRelativeMargin) + T(kAbsoluteMargin);
  }

 private:
  // The alpha cell [j, j+1] of `log_alpha` and the fraction t within it (clamped to the range).
  template <typename T>
  static T AlphaCell(const T& log_alpha, int* j_out) {
    const double log_min = std::log(kMinAlpha), log_max = std::log(kMaxAlpha);
    const double step = (log_max - log_min) / (kAlphaNodes - 1);
    const double x = (std::clamp(ValueOf(log_alpha), log_min, log_max) - log_min) / step;
    const int j = std::clamp(static_cast<int>(std::floor(x)), 0, kAlphaNodes - 2);
    *j_out = j;
    if (ValueOf(log_alpha) <= log_min || ValueOf(log_alpha) >= log_max) {
      return T(std::clamp(x - j, 0.0, 1.0));
    }
    return (log_alpha - T(log_min)) / T(step) - T(j);
  }

  // Catmull-Rom through alpha nodes j-1 .. j+2 (ends repeated) at fraction t of [j, j+1].
  template <typename T>
  T Interpolate(double (MicrofacetAlbedoTable::*at)(int, int) const, int j, int k,
                const T& t) const {
    const double p0 = (this->*at)(std::max(j - 1, 0), k), p1 = (this->*at)(j, k);
    const double p2 = (this->*at)(j + 1, k);
    const double p3 = (this->*at)(std::min(j + 2, kAlphaNodes - 1), k);
    const T t2 = t * t, t3 = t2 * t;
    return T(0.5) * (T(2 * p1) + T(p2 - p0) * t + T(2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 +
                     T(3 * (p1 - p2) + p3 - p0) * t3);
  }

  std::vector<double> e0_, e1_;
};

// The values the build integrated for the model named `name`: two arrays of NodeCount()
// (E0 then E1), or nullptr when the build made none for it.
const double* BuiltAlbedoTable(const char* name);

// The table of microfacet model M: the build's, or integrated on first use (thread-safe).
template <typename M>
const MicrofacetAlbedoTable& AlbedoTableOf() {
  static const MicrofacetAlbedoTable table = [] {
    const double* built = BuiltAlbedoTable(M::kName);
    if (built == nullptr) return MicrofacetAlbedoTable(FindModel(M::kName));
    const int n = MicrofacetAlbedoTable::NodeCount();
    return MicrofacetAlbedoTable(std::vector<double>(built, built + n),
                                 std::vector<double>(built + n, built + 2 * n));
  }();
  return table;
}

}  // namespace brdf::fitters
