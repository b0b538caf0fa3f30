// A model read at the geometries of `brdf measure`'s default schedule (hemisphere, 5 deg
// steps in theta_i, theta_o and phi_o; detectors within 2 deg of the beam skipped, as the
// instrument's arm blocks them), at the nominal directions, with multiplicative Gaussian noise
// and a sigma column that states it. Shared by the fit diagnostics tests and
// bench/stability_study (docs/stability.md), so the study's failures and the tests that catch
// them see the same data.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/angles.h"
#include "core/measurement.h"
#include "models/registry.h"

namespace brdf::testing {

struct SyntheticOptions {
  double noise = 0.01;            // relative, one standard deviation (0: noise-free)
  double theta_max_deg = 90.0;    // keep geometries with theta_i and theta_o at most this
  double outlier_fraction = 0.0;  // readings multiplied by `outlier_factor` (spikes)
  double outlier_factor = 10.0;
  uint64_t seed = 1;
  bool grazing_rings = false;  // add theta = 87 and 89 deg to the schedule's 0, 5, ..., 85
  double theta_step_deg = 5.0;
  double phi_step_deg = 5.0;
  double blocked_within_deg = 2.0;  // Instrument::blocked_within_deg's default
};

inline Measurement SynthesizeOnHemisphere(const Model& truth, const SyntheticOptions& options) {
  std::vector<double> thetas;
  for (double theta = 0; theta < 89; theta += options.theta_step_deg) thetas.push_back(theta);
  if (options.grazing_rings) thetas.insert(thetas.end(), {87.0, 89.0});
  Measurement measurement;
  measurement.format = "synthetic";
  measurement.source = truth.ToString();
  std::mt19937_64 random(options.seed);
  std::normal_distribution<double> gaussian;
  std::uniform_real_distribution<double> uniform;
  const double cos_blocked = std::cos(DegToRad(options.blocked_within_deg));
  const int phi_steps = static_cast<int>(std::lround(360.0 / options.phi_step_deg));
  for (double theta_i : thetas) {
    if (theta_i > options.theta_max_deg) continue;
    const Vec3 wi = SphericalDirection(DegToRad(theta_i), 0.0);
    for (double theta_o : thetas) {
      if (theta_o > options.theta_max_deg) continue;
      for (int k = 0; k < (theta_o == 0 ? 1 : phi_steps); ++k) {
        const Vec3 wo = SphericalDirection(DegToRad(theta_o), DegToRad(options.phi_step_deg * k));
        if (wi.dot(wo) > cos_blocked) continue;
        Sample sample;
        sample.wi = wi;
        sample.wo = wo;
        const Rgb value = truth.Eval(wi, wo);
        sample.value = value;
        for (int c = 0; c < 3; ++c) sample.value[c] *= 1.0 + options.noise * gaussian(random);
        if (uniform(random) < options.outlier_fraction) sample.value *= options.outlier_factor;
        measurement.samples.push_back(sample);
        if (options.noise > 0) measurement.sigma.push_back((options.noise * value).max(1e-12));
      }
    }
  }
  return measurement;
}

}  // namespace brdf::testing
