// The instrument's forward model (DESIGN §6, "fitting through the instrument"): what a
// calibrated value of `brdf measure` is in terms of the BRDF f, so that a fit compares a
// reading with the model as the instrument sees it. A value at nominal (wi, wo) is
//   value = R(wi, wo) · R_norm / (R_ref · cos theta_o),
// R the aperture average of instrument.h, R_ref the reference's reading through the same
// apertures and R_norm its ideal value (measure.h, Calibration), with R by the same quadrature
// the virtual instrument integrates with (aperture.h: the lobe-width rule). Hence
//   value = sum over nodes of weight · f(wi_node, wo_node).
// The arms' positioning jitter blurs the mean reading further: each aperture's rule is moved
// to the second and fourth radial moments of its points displaced by the jitter
// (forward_model.cpp). Not modelled: stray light (an
// offset, 0 by default).
#pragma once

#include <vector>

#include "gonio/aperture.h"
#include "gonio/instrument.h"

namespace brdf::gonio {

class ForwardModel {
 public:
  // The quadrature the virtual instrument uses for a lobe of angular width `lobe_width`
  // (radians; LobeWidth of the model, infinite for none).
  ForwardModel(const Instrument& instrument, double lobe_width);

  // Appends the nodes of the calibrated value at nominal (wi, wo).
  void AppendNodes(const Vec3& wi, const Vec3& wo, std::vector<ReadingNode>* nodes) const;
  // Nodes of a reading with every detector direction above the horizon.
  int PointsPerReading() const {
    return static_cast<int>(source_quadrature_.size() * detector_quadrature_.size());
  }

 private:
  Instrument instrument_;  // a point aperture widened by the jitter
  std::vector<AperturePoint> source_quadrature_, detector_quadrature_;
  double calibration_ = 1;  // R_norm / R_ref
};

}  // namespace brdf::gonio
