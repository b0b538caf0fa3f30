// Helpers shared by the gonio tests and the speed/accuracy study in bench/: an ideal
// instrument, a one-incidence schedule, and a reference aperture average computed by brute
// force, independently of the instrument's own quadrature (gonio/aperture.h).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "core/angles.h"
#include "gonio/height_field.h"
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

// Slope statistics of the triangles the tracer builds from a height field (two per cell, as in
// gonio/traced_surface.cpp: a-b-d and a-d-c), computed from their vertices, independently of
// HeightField::RmsSlope. Every triangle has the same projected area, so plain means over the
// triangles are the moments of the slope distribution Beckmann's D describes.
struct FacetSlopes {
  double rms = 0;       // sqrt(<|∇h|²>): Beckmann's alpha for a Gaussian surface
  double sigma_x = 0;   // standard deviation of ∂h/∂x (alpha/√2 for a Gaussian surface)
  double sigma_y = 0;   // of ∂h/∂y
  double kurtosis = 0;  // excess kurtosis of ∂h/∂x: 0 for a Gaussian
};

inline FacetSlopes MeasureFacetSlopes(const HeightField& field) {
  double sx = 0, sy = 0, sxx = 0, syy = 0, sx4 = 0;
  double count = 0;
  const auto add = [&](double p, double q) {
    sx += p, sy += q, sxx += p * p, syy += q * q, sx4 += p * p * p * p;
    count += 1;
  };
  for (int y = 0; y < field.resolution; ++y) {
    for (int x = 0; x < field.resolution; ++x) {
      const double a = field.At(x, y), b = field.At(x + 1, y), c = field.At(x, y + 1),
                   d = field.At(x + 1, y + 1);
      add(b - a, d - b);  // triangle a-b-d: (x, y), (x+1, y), (x+1, y+1)
      add(d - c, c - a);  // triangle a-d-c: (x, y), (x+1, y+1), (x, y+1)
    }
  }
  const double mx = sx / count, my = sy / count;
  const double vx = sxx / count - mx * mx, vy = syy / count - my * my;
  FacetSlopes slopes;
  slopes.rms = std::sqrt((sxx + syy) / count);
  slopes.sigma_x = std::sqrt(vx);
  slopes.sigma_y = std::sqrt(vy);
  slopes.kurtosis = (sx4 / count) / (vx * vx) - 3;
  return slopes;
}

}  // namespace brdf::gonio::testing
