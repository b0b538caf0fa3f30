// Chi-square test of a sampler of directions against its density, in the manner of pbrt-v4's
// bsdfs_test.cpp: directions drawn by `sample` are binned over the hemisphere in
// (cos theta, phi), 40 x 80 bins; each bin's expected count is `density` (per steradian)
// integrated over the bin by Simpson's rule (5 x 5 points); draws below the horizon form one more
// bin, expected to hold what the density leaves outside the hemisphere. Bins expecting fewer than
// 5 are pooled. The statistic is turned into a z-score by the Wilson-Hilferty cube-root
// approximation. Shared by the tests of every lobe sampler.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/angles.h"
#include "core/rng.h"
#include "core/vec.h"

namespace brdf::testing {

// `sample(u)` returns a direction for a uniform point u of [0, 1)^2; `density(w)` its density.
template <typename Sample, typename Density>
double DirectionChiSquareZ(Sample sample, Density density, int samples, uint64_t seed) {
  constexpr int kCosBins = 40, kPhiBins = 80;
  std::vector<double> observed(kCosBins * kPhiBins + 1, 0.0);
  Rng random(0, seed);
  for (int k = 0; k < samples; ++k) {
    const Vec3 wi = sample(random.Uniform2D());
    if (!(wi.z() > 0)) {
      observed.back() += 1;
      continue;
    }
    const int i = std::min(kCosBins - 1, static_cast<int>(wi.z() * kCosBins));
    double phi = std::atan2(wi.y(), wi.x());
    if (phi < 0) phi += 2 * kPi;
    const int j = std::min(kPhiBins - 1, static_cast<int>(phi / (2 * kPi) * kPhiBins));
    observed[i * kPhiBins + j] += 1;
  }
  std::vector<double> expected(observed.size(), 0.0);
  const double simpson[5] = {1, 4, 2, 4, 1};
  double inside = 0;
  for (int i = 0; i < kCosBins; ++i) {
    for (int j = 0; j < kPhiBins; ++j) {
      const double z0 = double(i) / kCosBins, phi0 = 2 * kPi * j / kPhiBins;
      const double dz = 1.0 / kCosBins, dphi = 2 * kPi / kPhiBins;
      double integral = 0;
      for (int a = 0; a < 5; ++a) {
        for (int b = 0; b < 5; ++b) {
          const double z = z0 + dz * a / 4, phi = phi0 + dphi * b / 4;
          const double r = std::sqrt(std::max(0.0, 1 - z * z));
          integral +=
              simpson[a] * simpson[b] * density(Vec3(r * std::cos(phi), r * std::sin(phi), z));
        }
      }
      integral *= dz * dphi / 144.0;  // (1/12)^2 of Simpson's 4-panel weights
      expected[i * kPhiBins + j] = integral * samples;
      inside += integral;
    }
  }
  expected.back() = std::max(0.0, 1.0 - inside) * samples;
  double chi_square = 0, pooled_observed = 0, pooled_expected = 0;
  int bins = 0;
  for (size_t k = 0; k < observed.size(); ++k) {
    if (expected[k] < 5) {
      pooled_observed += observed[k];
      pooled_expected += expected[k];
      continue;
    }
    chi_square += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++bins;
  }
  if (pooled_expected >= 5) {
    chi_square +=
        (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
    ++bins;
  }
  const double dof = bins - 1;
  return (std::cbrt(chi_square / dof) - (1 - 2 / (9 * dof))) / std::sqrt(2 / (9 * dof));
}

}  // namespace brdf::testing
