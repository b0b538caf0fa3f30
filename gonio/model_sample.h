// Sample 1, `model:MODEL`: a flat sample with an analytic BRDF (DESIGN §5). The cheapest
// sample and the reference for the others: nothing is traced; the instrument's apertures are
// integrated by deterministic equal-area quadrature with as many points as the lobe needs
// (aperture.h).
#pragma once

#include "gonio/aperture.h"
#include "gonio/sample.h"
#include "models/registry.h"

namespace brdf::gonio {

// The Spectralon-like reference: lambert with rho_d = rho in every channel.
Model LambertReference(double rho);

class ModelSample : public GonioSample {
 public:
  ModelSample(Model model, const Instrument& instrument);

  std::string Modelled() const override;
  Readings Measure(const Instrument& instrument, const Vec3& wi, const std::vector<Vec3>& detectors,
                   uint64_t seed, uint64_t incidence_index) const override;

  // The reading of one detector (exposed for the reference and for tests).
  Rgb Reading(const Instrument& instrument, const Vec3& wi, const Vec3& wo) const;
  bool HasExpectedReading() const override { return true; }
  Rgb ExpectedReading(const Instrument& instrument, const Vec3& wi, const Vec3& wo) const override {
    return Reading(instrument, wi, wo);
  }

  // Scales the lobe-width rule's density (for the speed/accuracy study in bench/).
  void SetApertureDensity(const Instrument& instrument, double density);
  int source_points() const { return static_cast<int>(source_quadrature_.size()); }
  int detector_points() const { return static_cast<int>(detector_quadrature_.size()); }
  const Model& model() const { return model_; }

 private:
  Model model_;
  double lobe_width_ = 0;
  std::vector<AperturePoint> source_quadrature_, detector_quadrature_;
};

}  // namespace brdf::gonio
