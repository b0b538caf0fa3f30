// How finely the instrument integrates over its apertures: "as many points as the lobe's width
// requires" (DESIGN §5). An aperture is a cone of angular radius a; its points are a polar
// product rule on the equal-area disk that maps onto the cone (sampling.h, SampleUniformCone):
// Gauss-Legendre in the area fraction u = r² times the trapezoid rule in azimuth. Both converge
// spectrally for smooth integrands — the trapezoid rule is exponentially accurate for periodic
// functions (Trefethen & Weideman, SIAM Review 56(3), 2014).
//
// The rule: a lobe of angular width sigma seen through radius a varies on the scale q = a/sigma
// aperture radii, so rings = ceil(q + 1/2) and spokes = ceil(2π q + 3): about one ring per lobe
// width and one spoke per lobe width of circumference, plus a floor. The floor (one ring of
// four spokes) integrates the quadratic variation of a smooth BRDF times cos(theta_o) exactly.
// `density` scales the rule; the total is capped at kMaxAperturePoints. docs/gonio.md shows the
// error against the number of points for a sharp lobe.
#pragma once

#include <vector>

#include "gonio/instrument.h"
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

// Calls visit(wi_source, weight) for every point of the source quadrature around the nominal
// incidence `wi`, the weight combining the quadrature weight and the point's relative
// irradiance (Instrument::SourceDirection); returns the sum of the weights, to normalise by.
template <typename Visit>
double ForEachSourceDirection(const Instrument& instrument, const Vec3& wi,
                              const std::vector<AperturePoint>& source_quadrature, Visit&& visit) {
  double weight_sum = 0;
  for (const AperturePoint& point : source_quadrature) {
    double irradiance = 1;
    const Vec3 wi_source = instrument.SourceDirection(wi, point.u1, point.u2, &irradiance);
    const double weight = point.weight * irradiance;
    weight_sum += weight;
    if (weight > 0) visit(wi_source, weight);
  }
  return weight_sum;
}

// One point of a reading's quadrature: a direction of the source, one of the detector, and the
// point's weight in the reading.
struct ReadingNode {
  Vec3 wi, wo;
  double weight = 0;
};

// Appends the nodes of the reading at nominal (wi, wo) (instrument.h):
//   R = sum over nodes of weight f(wi_node, wo_node),
// the weights holding the source's irradiance, the quadrature weights and cos(theta_o) of the
// detector direction, normalised by the source's weight sum. Detector directions at or below
// the horizon see nothing and are left out. ModelSample reads its samples through these nodes
// and a fit through an instrument predicts its readings with them (fitters/reading_nodes.h).
void AppendReadingNodes(const Instrument& instrument,
                        const std::vector<AperturePoint>& source_quadrature,
                        const std::vector<AperturePoint>& detector_quadrature, const Vec3& wi,
                        const Vec3& wo, std::vector<ReadingNode>* nodes);

}  // namespace brdf::gonio
