// The ray-traced micro-geometry sample: an Embree triangle mesh of a periodic height field
// (two triangles per cell), lit by rays from the source and followed through up to `bounces`
// facet interactions. Each facet scatters by its base material (facet_material.h); a path
// that leaves the tile sideways re-enters on the opposite side (the height field is periodic),
// one that rises above the highest point has escaped toward the detectors. Paths whose weight
// has become small end by Russian roulette (Arvo & Kirk, "Particle transport and image
// synthesis", SIGGRAPH 1990), which keeps the estimate unbiased.
#pragma once

#include <memory>

#include "gonio/facet_material.h"
#include "gonio/height_field.h"
#include "gonio/sample.h"
#include "gonio/surface_sample.h"

namespace brdf::gonio {

class EmbreeHeightField;  // the BVH, in traced_surface.cpp

class TracedSurfaceSample : public GonioSample {
 public:
  TracedSurfaceSample(HeightField field, FacetMaterial material, const SurfaceSpec& spec);
  ~TracedSurfaceSample() override;

  // One incidence traced: power reaching each detector cone and in total, per unit of
  // incident power (the incident power is the sum of the rays' source weights).
  struct Trace {
    std::vector<Rgb> detector_power;
    std::vector<Rgb> detector_power_standard_error;  // Monte Carlo, from the spread of batches
    Rgb reflected = Rgb::Zero();                     // escaped upward, any direction
    int64_t escaped = 0;                             // paths that escaped upward
    double incident = 0;
    int64_t segments = 0;   // ray segments traced (Embree queries)
    int64_t paths_cut = 0;  // paths still carrying weight at the bounce limit
  };
  Trace TraceIncidence(const Instrument& instrument, const Vec3& wi,
                       const std::vector<Vec3>& detectors, uint64_t seed, uint64_t incidence_index,
                       int64_t rays) const;

  std::string Modelled() const override;
  Readings Measure(const Instrument& instrument, const Vec3& wi, const std::vector<Vec3>& detectors,
                   uint64_t seed, uint64_t incidence_index) const override;

  const HeightField& field() const { return field_; }

 private:
  HeightField field_;
  FacetMaterial material_;
  SurfaceSpec spec_;
  std::unique_ptr<EmbreeHeightField> scene_;
};

}  // namespace brdf::gonio
