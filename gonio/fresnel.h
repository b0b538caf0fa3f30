// Exact Fresnel reflectance of a smooth interface from air (Born & Wolf, Principles of Optics,
// §1.5.2 for dielectrics and §14.2 for absorbing media): with the complex relative index
// eta = n + i k and Snell's law written for complex angles, cos(theta_t) = sqrt(1 − sin²θ/eta²),
//   r_s = (cos θ − eta cos θ_t) / (cos θ + eta cos θ_t),
//   r_p = (eta cos θ − cos θ_t) / (eta cos θ + cos θ_t),
// and unpolarized light reflects R = (|r_s|² + |r_p|²) / 2. k = 0 is a dielectric.
#pragma once

#include <algorithm>
#include <complex>

namespace brdf::gonio {

inline double FresnelReflectance(double cos_theta, double n, double k) {
  cos_theta = std::clamp(cos_theta, 0.0, 1.0);
  const std::complex<double> eta(n, k);
  const double sin_squared = 1.0 - cos_theta * cos_theta;
  const std::complex<double> cos_transmitted = std::sqrt(1.0 - sin_squared / (eta * eta));
  const std::complex<double> r_s =
      (cos_theta - eta * cos_transmitted) / (cos_theta + eta * cos_transmitted);
  const std::complex<double> r_p =
      (eta * cos_theta - cos_transmitted) / (eta * cos_theta + cos_transmitted);
  return 0.5 * (std::norm(r_s) + std::norm(r_p));
}

}  // namespace brdf::gonio
