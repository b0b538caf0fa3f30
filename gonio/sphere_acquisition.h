// Sample 3, `sphere:MODEL`: image-based acquisition as in the MERL database (Matusik,
// Pfister, Brand & McMillan, "A Data-Driven Reflectance Model", SIGGRAPH 2003). A camera
// views a sphere of the material lit by a distant source; the sphere is a triangle mesh
// rasterized once (rasterizer.h) and every covered pixel yields one (wi, wo, value) sample per
// light position. As in the real acquisition, the geometry of a pixel is computed from the
// known ideal sphere (the camera ray meets the sphere: normal, wo), while the image itself
// is the mesh shaded with its interpolated normals — so tessellation error shows up as
// measurement error. Values are calibrated per pixel against an image of a Lambertian
// reference sphere (rho = reference.rho) under the same light: value = counts/counts_ref · rho/π.
//
// Light positions: for each distinct theta_i of the schedule the light sits 2·theta_i from the
// camera axis (in the camera's horizontal plane), so the pixel whose normal bisects light and
// camera sees theta_i = theta_o; the `merl` schedule uses theta_i = 0, 5, ..., 85°. The
// schedule's detector directions do not apply: the camera's pixels are the detectors.
#pragma once

#include <cstdint>
#include <functional>

#include "core/measurement.h"
#include "gonio/instrument.h"
#include "gonio/rasterizer.h"
#include "gonio/schedule.h"
#include "models/registry.h"

namespace brdf::gonio {

std::vector<double> SphereLightThetas(const Schedule& schedule);

class SphereAcquisition {
 public:
  SphereAcquisition(Model model, const Instrument& instrument);

  std::string Modelled() const;
  // Appends the samples (with sigma) of every light position to `measurement`, in light then
  // pixel order; `advance` (may be empty) is told of each finished view. Under MPI the views
  // are split across ranks (core/parallel_ranks.h) and only rank 0's `measurement` is filled.
  void Acquire(const Schedule& schedule, uint64_t seed, const std::function<void(int64_t)>& advance,
               Measurement* measurement) const;

  // One light position (angle from the camera axis, radians), shaded from `gbuffer`: for the
  // benchmark and tests. Pixels without a sample are left out.
  struct View {
    std::vector<Sample> samples;
    std::vector<Rgb> sigma;
  };
  View Shade(const GBuffer& gbuffer, double light_angle, uint64_t seed, uint64_t view_index) const;

  const PinholeCamera& camera() const { return camera_; }
  const TriangleMesh& mesh() const { return mesh_; }

 private:
  Model model_;
  const Instrument& instrument_;
  PinholeCamera camera_;
  TriangleMesh mesh_;
};

}  // namespace brdf::gonio
