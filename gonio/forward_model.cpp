#include "gonio/forward_model.h"

#include <cmath>

#include "core/angles.h"
#include "gonio/measure.h"

namespace brdf::gonio {
namespace {

// The instrument whose apertures' second moments are those of the jittered ones: the arms'
// positioning jitter (Gaussian, sigma per axis, measure.cpp) blurs the expected reading, and a
// cone of radius a has per-axis variance a²/4, so the jittered cone's second moments are those
// of radius sqrt(a² + 4 sigma²). A lobe seen through it is blurred as the mean of the jittered
// readings is up to the second moments. The fourth radial moments differ: the jittered cone's is
// a⁴/3 + 4 a² sigma² + 8 sigma⁴, the widened cone's a⁴/3 + (8/3) a² sigma² + (16/3) sigma⁴,
// short by 4 sigma²/a² relative to leading order (1 % for the default instrument's detector,
// 16 % for its source), which a lobe about as narrow as the detector feels (docs/planning.md).
// A point lamp's spot is kept as it is.
Instrument Jittered(const Instrument& instrument) {
  Instrument jittered = instrument;
  const double sigma = DegToRad(instrument.jitter_deg);
  if (sigma <= 0) return jittered;
  const auto widen = [&](double radius) { return std::sqrt(radius * radius + 4 * sigma * sigma); };
  if (instrument.source_kind == Instrument::SourceKind::kCollimated) {
    jittered.source_angular_radius_deg = RadToDeg(widen(instrument.SourceAngularRadius()));
  }
  const double detector = widen(std::acos(instrument.DetectorCosHalfAngle()));
  jittered.detector_solid_angle_sr = 2 * kPi * (1 - std::cos(detector));
  return jittered;
}

}  // namespace

ForwardModel::ForwardModel(const Instrument& instrument, double lobe_width)
    : instrument_(Jittered(instrument)),
      // As ModelSample integrates: the source cone as densely as the detector cone, relative to
      // its own radius (model_sample.cpp).
      source_quadrature_(ApertureQuadrature(instrument_.SourceAngularRadius(), lobe_width)),
      detector_quadrature_(
          ApertureQuadrature(std::acos(instrument_.DetectorCosHalfAngle()), lobe_width)) {
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
