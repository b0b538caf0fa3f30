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

ModelSample::ModelSample(Model model, const Instrument& instrument) : model_(std::move(model)) {
  const double lobe_width = LobeWidth(model_);
  // A shift of the incidence moves the mirror lobe by the same angle, so the source cone needs
  // the same density of points as the detector cone, relative to its own radius.
  source_points_ = AperturePoints(instrument.SourceAngularRadius(), lobe_width);
  detector_points_ = AperturePoints(std::acos(instrument.DetectorCosHalfAngle()), lobe_width);
}

std::string ModelSample::Modelled() const {
  return "flat sample with analytic BRDF " + model_.ToString() + "; aperture quadrature " +
         std::to_string(source_points_) + " source x " + std::to_string(detector_points_) +
         " detector points (lobe width rule); no ray tracing";
}

Rgb ModelSample::Reading(const Instrument& instrument, const Vec3& wi, const Vec3& wo) const {
  const double cos_detector = instrument.DetectorCosHalfAngle();
  const Frame detector_frame(wo);
  Rgb sum = Rgb::Zero();
  double weight_sum = 0;
  for (int s = 0; s < source_points_; ++s) {
    double u1 = 0.5, u2 = 0;
    if (source_points_ > 1) VogelPoint(s, source_points_, &u1, &u2);
    double weight = 1;
    const Vec3 wi_source =
        source_points_ > 1 ? instrument.SourceDirection(wi, u1, u2, &weight) : wi;
    weight_sum += weight;
    if (weight <= 0) continue;
    Rgb detector_sum = Rgb::Zero();
    for (int d = 0; d < detector_points_; ++d) {
      double v1 = 0, v2 = 0;
      VogelPoint(d, detector_points_, &v1, &v2);
      const Vec3 wo_detector =
          detector_points_ > 1 ? detector_frame.FromLocal(SampleUniformCone(v1, v2, cos_detector))
                               : wo;
      if (wo_detector.z() <= 0) continue;
      detector_sum += model_.Eval(wi_source, wo_detector) * wo_detector.z();
    }
    sum += weight * detector_sum / detector_points_;
  }
  return weight_sum > 0 ? Rgb(sum / weight_sum) : Rgb(Rgb::Zero());
}

std::vector<Rgb> ModelSample::Measure(const Instrument& instrument, const Vec3& wi,
                                      const std::vector<Vec3>& detectors, uint64_t /*seed*/,
                                      uint64_t /*incidence_index*/) const {
  std::vector<Rgb> readings(detectors.size(), Rgb::Zero());
  tbb::parallel_for(size_t{0}, detectors.size(),
                    [&](size_t k) { readings[k] = Reading(instrument, wi, detectors[k]); });
  return readings;
}

}  // namespace brdf::gonio
