// How finely the instrument integrates over its apertures: "as many points as the lobe's width
// requires" (DESIGN §5). An aperture is a cone of angular radius a; its points are a polar
// product rule on the equal-area disk that maps onto the cone (sampling.h, SampleUniformCone):
// Gauss-Legendre in the radius (weighted by r) times the trapezoid rule in azimuth, which
// converge spectrally for smooth integrands — the trapezoid rule is exponentially accurate for
// periodic functions (Trefethen & Weideman, SIAM Review 56(3), 2014).
//
// The rule: a lobe of angular width sigma seen through radius a varies on the scale q = a/sigma
// aperture radii, so rings = ceil(q + 2) and spokes = ceil(2π q + 6): about one ring per lobe
// width plus two, and one spoke per lobe width of circumference plus six (at least two rings and
// six spokes, which integrate the cos(theta_o) variation of a smooth BRDF exactly to second
// order), scaled by `density` and capped at kMaxAperturePoints. docs/gonio.md shows the error
// against the number of points for a sharp lobe: the rule lands near 1e-5, where halving the
// points would still give 1e-3 and a third of them 4%.
#pragma once

#include <vector>

#include "models/registry.h"

namespace brdf::gonio {

inline constexpr int kMaxAperturePoints = 4096;

// A point (u1, u2) of the unit square for SampleUniformCone and its weight; weights sum to 1.
struct AperturePoint {
  double u1 = 0, u2 = 0, weight = 1;
};

// Angular half-width (radians) at which the model's glossy lobe has fallen to e^(-1/2) of its
// peak above the diffuse floor, probed numerically at normal incidence along theta_o; infinity
// when the model has no lobe (e.g. lambert) — so the rule works for any registered model.
double LobeWidth(const Model& model);

// The quadrature for an aperture of angular radius `aperture_radius` (radians) and a lobe of
// angular width `lobe_width` (radians; infinite for none, 0 for a delta). A point aperture
// (radius 0) is its centre alone. `density` scales rings and spokes (1 = the rule).
std::vector<AperturePoint> ApertureQuadrature(double aperture_radius, double lobe_width,
                                              double density = 1.0);

}  // namespace brdf::gonio
