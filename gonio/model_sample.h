// Sample 1, `model:MODEL`: a flat sample with an analytic BRDF (DESIGN §5). The cheapest
// sample and the reference for the others: nothing is traced; the instrument's apertures are
// integrated by deterministic equal-area quadrature with as many points as the lobe needs
// (aperture.h).
#pragma once

#include "gonio/sample.h"
#include "models/registry.h"

namespace brdf::gonio {

// The Spectralon-like reference: lambert with rho_d = rho in every channel.
Model LambertReference(double rho);

class ModelSample : public GonioSample {
 public:
  ModelSample(Model model, const Instrument& instrument);

  std::string Modelled() const override;
  std::vector<Rgb> Measure(const Instrument& instrument, const Vec3& wi,
                           const std::vector<Vec3>& detectors, uint64_t seed,
                           uint64_t incidence_index) const override;

  // The reading of one detector (exposed for the reference and for tests).
  Rgb Reading(const Instrument& instrument, const Vec3& wi, const Vec3& wo) const;

  // Overrides the lobe-width rule (for the speed/accuracy study in bench/).
  void SetAperturePoints(int source_points, int detector_points) {
    source_points_ = source_points;
    detector_points_ = detector_points;
  }
  int source_points() const { return source_points_; }
  int detector_points() const { return detector_points_; }
  const Model& model() const { return model_; }

 private:
  Model model_;
  int source_points_ = 1;
  int detector_points_ = 1;
};

}  // namespace brdf::gonio
