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
  // Target absolute error of the albedo, per channel. The Kronrod-minus-Gauss estimate is
  // pessimistic: at 1e-5 the true error of a whole curve stays below 1e-6 for exponents 1..1e4
  // (docs/energy.md), well inside the 1e-4 that an energy check needs.
  double tolerance = 1e-5;
  int max_intervals = 200;  // cap on the adaptive subdivisions (each costs 15 x 15 evaluations)

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
