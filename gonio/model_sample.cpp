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
  const double cos_detector = instrument.DetectorCosHalfAngle();
  const Frame detector_frame = Frame::FromZ(wo);
  Rgb sum = Rgb::Zero();
  const double weight_sum = ForEachSourceDirection(
      instrument, wi, source_quadrature_, [&](const Vec3& wi_source, double weight) {
        Rgb detector_sum = Rgb::Zero();
        for (const AperturePoint& detector : detector_quadrature_) {
          const Vec3 wo_detector = detector_frame.FromLocal(
              SampleUniformCone(Point2(detector.u1, detector.u2), cos_detector));
          if (wo_detector.z() <= 0) continue;
          detector_sum += detector.weight * model_.Eval(wi_source, wo_detector) * wo_detector.z();
        }
        sum += weight * detector_sum;
      });
  return weight_sum > 0 ? Rgb(sum / weight_sum) : Rgb(Rgb::Zero());
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
