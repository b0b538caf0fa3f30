// Deterministic albedo quadrature in coordinates centred on a lobe. A sharp lobe (exponent
// 1e4 is a lobe about half a degree wide) defeats any fixed theta/phi grid; here the polar angle
// about the lobe's centre is warped by the lobe's own power-cosine CDF, so the lobe is spread
// evenly over the integration variable whatever its exponent, and the azimuth runs only over
// the arc of each ring that lies above the horizon, so the integrand has no kink inside the
// domain. An adaptive Gauss-Kronrod rule then gives the value and an error estimate.
#pragma once

#include "energy/integrand.h"

namespace brdf {

struct LobeQuadratureOptions {
  double tolerance = 1e-6;  // target absolute error of the albedo, per channel
  int max_intervals = 200;  // cap on the adaptive subdivisions (each costs 15 x 30 evaluations)

  void Validate() const;  // throws UsageError
};

// ∫_H f(wi, wo) cos(theta_i) dwi for one wo, in the given lobe coordinates.
AlbedoEstimate IntegrateInLobeCoordinates(const BrdfFunction& brdf, const Vec3& wo,
                                          const LobeCoordinates& coordinates,
                                          const LobeQuadratureOptions& options);

// The naive rule, kept to show where it fails: the midpoint rule on a uniform grid of
// theta_cells x phi_cells over the hemisphere in wi. No error estimate (error stays zero).
AlbedoEstimate IntegrateOnUniformGrid(const BrdfFunction& brdf, const Vec3& wo, int theta_cells,
                                      int phi_cells);

}  // namespace brdf
