// Helpers shared by the gonio tests and the speed/accuracy study in bench/: an ideal
// instrument, a one-incidence schedule, and a reference aperture average computed by brute
// force, independently of the instrument's own quadrature (gonio/aperture.h).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "core/angles.h"
#include "gonio/instrument.h"
#include "gonio/schedule.h"
#include "models/registry.h"

namespace brdf::gonio::testing {

// No shot or read noise, no positioning jitter: readings are the expected values.
inline Instrument IdealInstrument() {
  Instrument instrument;
  instrument.photons = 0;
  instrument.jitter_deg = 0;
  return instrument;
}

inline Schedule OneIncidence(double theta_i_deg, const std::vector<Vec3>& detectors) {
  Schedule schedule;
  schedule.spec = schedule.kind = "test";
  Incidence incidence{SphericalDirection(DegToRad(theta_i_deg), 0), {}};
  for (const Vec3& wo : detectors) incidence.detectors.push_back({wo, 0});
  schedule.incidences.push_back(incidence);
  return schedule;
}

// (1/Ω) ∫_cone f(wi, wo) cos(theta_o) dω (red channel) over a cone of half-angle `cone` about
// `axis`, by the midpoint rule in (polar offset rho, azimuth) with dω = sin(rho) drho dphi.
inline double ApertureAverageByGrid(const Model& model, const Vec3& wi, const Vec3& axis,
                                    double cone, int steps) {
  const Vec3 helper = std::abs(axis.z()) < 0.9 ? Vec3(0, 0, 1) : Vec3(1, 0, 0);
  const Vec3 u = axis.cross(helper).normalized(), v = axis.cross(u);
  double integral = 0, solid_angle = 0;
  for (int i = 0; i < steps; ++i) {
    const double rho = (i + 0.5) * cone / steps;
    for (int j = 0; j < steps; ++j) {
      const double phi = (j + 0.5) * 2 * kPi / steps;
      const Vec3 wo =
          std::cos(rho) * axis + std::sin(rho) * (std::cos(phi) * u + std::sin(phi) * v);
      const double dw = std::sin(rho);
      integral += model.Eval(wi, wo)[0] * wo.z() * dw;
      solid_angle += dw;
    }
  }
  return integral / solid_angle;
}

}  // namespace brdf::gonio::testing
