#include "gonio/forward_model.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/angles.h"
#include "gonio/measure.h"

namespace brdf::gonio {
namespace {

// The aperture rule of a cone of angular radius `radius` (ApertureQuadrature: the rule the
// virtual instrument integrates with) as the forward model uses it when the arm that carries
// the cone is jittered (Gaussian, `sigma` radians per axis, measure.cpp). The mean of the
// jittered readings integrates the model over the rule's points each displaced by the jitter.
// For an isotropic spread of offsets z about the nominal direction (the rule's spokes are
// isotropic to fourth order from five on; the virtual instrument's own rule shares the floor of
// four), that mean agrees with the model's own average over a
// rule of the same offsets' radial moments E|z|² and E|z|⁴ up to fifth order in z. A point at
// angle r displaced by the jitter has E|z|² = r² + 2 sigma² and E|z|⁴ = r⁴ + 8 sigma² r² +
// 8 sigma⁴. The rule keeps its points and weights and moves each ring from r² to a + b r², a and
// b chosen to match both moments of the jittered rule. A rule of one ring cannot: it gets a
// point at the centre besides. A point aperture is widened to the cone of radius 2 sigma, whose
// second moment is the jitter's, and a rule whose inner rings would have to move inside the
// axis to the cone of radius sqrt(radius² + 4 sigma²), whose second moment is the jittered
// cone's. Returns the rule; *encoding is the radius of the cone its area
// fractions u1 refer to (radius, or the widened one).
std::vector<AperturePoint> JitteredRule(double radius, double lobe_width, double sigma,
                                        double* encoding) {
  *encoding = radius;
  std::vector<AperturePoint> rule = ApertureQuadrature(radius, lobe_width);
  if (sigma <= 0) return rule;
  const double one_minus_cos = 1 - std::cos(radius);
  std::vector<double> r2(rule.size());
  double mean = 0, square = 0;
  for (size_t k = 0; k < rule.size(); ++k) {
    const double r = std::acos(std::max(-1.0, 1 - rule[k].u1 * one_minus_cos));
    r2[k] = r * r;
    mean += rule[k].weight * r2[k];
    square += rule[k].weight * r2[k] * r2[k];
  }
  const double spread = square - mean * mean;  // of r² over the rule
  const double s2 = sigma * sigma;
  if (!(mean > 0)) {  // a point aperture
    *encoding = 2 * sigma;
    return ApertureQuadrature(*encoding, lobe_width);
  }
  if (!(spread > 1e-12 * mean * mean)) {
    // One ring at r: moved to rho² = E|z|⁴ / E|z|² with the weight w = (E|z|²)² / E|z|⁴, and
    // the centre holding the rest, 1 - w, match both moments.
    const double second = mean + 2 * s2, fourth = square + 8 * s2 * mean + 8 * s2 * s2;
    const double rho = std::sqrt(fourth / second), share = second * second / fourth;
    for (AperturePoint& point : rule) {
      point.u1 = (1 - std::cos(rho)) / one_minus_cos;
      point.weight *= share;
    }
    rule.push_back({0.0, 0.0, 1 - share});
    return rule;
  }
  const double jittered_spread = spread + 4 * s2 * mean + 4 * s2 * s2;
  const double b = std::sqrt(jittered_spread / spread), a = mean + 2 * s2 - b * mean;
  if (a + b * *std::min_element(r2.begin(), r2.end()) < 0) {
    // An inner ring would need a negative r² (rings well inside 2 sigma: a lobe far sharper than
    // the aperture): the cone widened to the jittered one's second moments instead.
    *encoding = std::sqrt(radius * radius + 4 * s2);
    return ApertureQuadrature(*encoding, lobe_width);
  }
  for (size_t k = 0; k < rule.size(); ++k) {
    rule[k].u1 = (1 - std::cos(std::sqrt(a + b * r2[k]))) / one_minus_cos;
  }
  return rule;
}

}  // namespace

ForwardModel::ForwardModel(const Instrument& instrument, double lobe_width)
    : instrument_(instrument) {
  // As ModelSample integrates: the source cone as densely as the detector cone, relative to its
  // own radius (model_sample.cpp). A point lamp's spot is kept as it is.
  const double sigma = DegToRad(instrument.jitter_deg);
  double source = instrument.SourceAngularRadius();
  if (instrument.source_kind == Instrument::SourceKind::kCollimated) {
    source_quadrature_ = JitteredRule(source, lobe_width, sigma, &source);
    instrument_.source_angular_radius_deg = RadToDeg(source);
  } else {
    source_quadrature_ = ApertureQuadrature(source, lobe_width);
  }
  const double detector = std::acos(instrument.DetectorCosHalfAngle());
  double encoding = detector;
  detector_quadrature_ = JitteredRule(detector, lobe_width, sigma, &encoding);
  if (encoding != detector)
    instrument_.detector_solid_angle_sr = 2 * kPi * (1 - std::cos(encoding));
  const double ideal =
      instrument.reference_rho * kInvPi * std::cos(DegToRad(instrument.reference_theta_o_deg));
  calibration_ = ideal / ReferenceReading(instrument);
}

void ForwardModel::AppendNodes(const Vec3& wi, const Vec3& wo,
                               std::vector<ReadingNode>* nodes) const {
  const size_t first = nodes->size();
  AppendReadingNodes(instrument_, source_quadrature_, detector_quadrature_, wi, wo, nodes);
  const double scale = calibration_ / wo.z();
  for (size_t n = first; n < nodes->size(); ++n) (*nodes)[n].weight *= scale;
}

}  // namespace brdf::gonio
