#include "gonio/model_sample.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "core/text.h"
#include "gonio/aperture.h"
#include "gonio/sampling.h"

namespace brdf::gonio {

Model LambertReference(double rho) {
  return Model(FindModel(models::Lambert::kName), std::vector<double>(3, rho));
}

ModelSample::ModelSample(Model model, const Instrument& instrument)
    : model_(std::move(model)), lobe_width_(LobeWidth(model_)) {
  SetApertureDensity(instrument, 1.0);
}

void ModelSample::SetApertureDensity(const Instrument& instrument, double density) {
  // A shift of the incidence moves the mirror lobe by the same angle, so the source cone needs
  // the same density of points as the detector cone, relative to its own radius.
  source_quadrature_ = ApertureQuadrature(instrument.SourceAngularRadius(), lobe_width_, density);
  detector_quadrature_ =
      ApertureQuadrature(std::acos(instrument.DetectorCosHalfAngle()), lobe_width_, density);
}

std::string ModelSample::Modelled() const {
  return "flat sample with analytic BRDF " + model_.ToString() + "; aperture quadrature " +
         std::to_string(source_points()) + " source x " + std::to_string(detector_points()) +
         " detector points (lobe width rule); no ray tracing";
}

Rgb ModelSample::Reading(const Instrument& instrument, const Vec3& wi, const Vec3& wo) const {
  std::vector<ReadingNode> nodes;
  nodes.reserve(source_quadrature_.size() * detector_quadrature_.size());
  AppendReadingNodes(instrument, source_quadrature_, detector_quadrature_, wi, wo, &nodes);
  Rgb sum = Rgb::Zero();
  for (const ReadingNode& node : nodes) sum += node.weight * model_.Eval(node.wi, node.wo);
  return sum;
}

Readings ModelSample::Measure(const Instrument& instrument, const Vec3& wi,
                              const std::vector<Vec3>& detectors, uint64_t /*seed*/,
                              uint64_t /*incidence_index*/) const {
  Readings readings;
  readings.value.assign(detectors.size(), Rgb::Zero());
  tbb::parallel_for(size_t{0}, detectors.size(),
                    [&](size_t k) { readings.value[k] = Reading(instrument, wi, detectors[k]); });
  return readings;
}

}  // namespace brdf::gonio
