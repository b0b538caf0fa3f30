// Sample 2, `surface:FILE.json`: a micro-geometry height field whose facets carry a base
// material, measured by ray tracing with Embree so that masking, shadowing and
// interreflection emerge (a virtual gonioreflectometer in the sense of Westin, Arvo &
// Torrance, "Predicting reflectance functions from complex surfaces", SIGGRAPH 1992).
//
// FILE.json (every field optional):
//   { "heightfield": { "kind": "flat" | "gaussian" | "v-grooves" | "file",
//                      "rms_slope": 0.3, "rms_slope_y": 0.3, "resolution": 256, "seed": 1,
//                      "correlation": 4, "period": 16, "path": "height.exr" },
//     "base": "lambert:rho_d=0.8" | "conductor:ior=N:k=K" | "dielectric:ior=N",
//     "bounces": 8, "rays_per_incidence": 1000000 }
// A relative "path" is resolved against the JSON file's directory.
//
// Model no more than the sample needs: a flat height field is not traced (no BVH is built):
// with a model base it is the analytic sample; with a smooth conductor or dielectric it is a
// mirror whose reading is the Fresnel reflectance of each source direction whose mirror image
// falls in the detector.
#pragma once

#include <memory>
#include <string>

#include "gonio/aperture.h"
#include "gonio/facet_material.h"
#include "gonio/height_field.h"
#include "gonio/sample.h"

namespace brdf::gonio {

struct SurfaceSpec {
  HeightFieldSpec heightfield;
  std::string base = "lambert:rho_d=0.8";
  int bounces = 8;
  int rays_per_incidence = 1000000;
};

// Reads and validates FILE.json; throws InputError naming the file and field.
SurfaceSpec ReadSurfaceSpec(const std::string& path);

std::unique_ptr<GonioSample> MakeSurfaceSample(const SurfaceSpec& spec,
                                               const Instrument& instrument);
std::unique_ptr<GonioSample> MakeSurfaceSample(const std::string& path,
                                               const Instrument& instrument);

// A flat smooth conductor or dielectric: a mirror, measured without tracing.
class FlatSpecularSample : public GonioSample {
 public:
  FlatSpecularSample(FacetMaterial material, const Instrument& instrument);
  std::string Modelled() const override;
  Readings Measure(const Instrument& instrument, const Vec3& wi, const std::vector<Vec3>& detectors,
                   uint64_t seed, uint64_t incidence_index) const override;

 private:
  FacetMaterial material_;
  std::vector<AperturePoint> source_quadrature_;
};

}  // namespace brdf::gonio
