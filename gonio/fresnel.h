// Exact Fresnel reflectance of a smooth interface from air for unpolarized light, with the
// relative index n + i k (k = 0: a dielectric). Written in real arithmetic (Born & Wolf,
// Principles of Optics, §14.2; the form given by Cook & Torrance 1982 for metals): with
//   a² + b² = sqrt((n² − k² − sin²θ)² + 4 n² k²),   a² = (a² + b² + n² − k² − sin²θ) / 2,
//   R_s = (a² + b² − 2a cos θ + cos²θ) / (a² + b² + 2a cos θ + cos²θ),
//   R_p = R_s ((a² + b²) cos²θ − 2a cos θ sin²θ + sin⁴θ) / ((a² + b²) cos²θ + 2a cos θ sin²θ +
//   sin⁴θ),
// R = (R_s + R_p) / 2. Equal to |r_s|² and |r_p|² of the complex Fresnel amplitudes (the
// surface tests check it against that form); real arithmetic avoids complex sqrt and division
// in the tracer's inner loop.
#pragma once

#include <algorithm>
#include <cmath>

namespace brdf::gonio {

inline double FresnelReflectance(double cos_theta, double n, double k) {
  cos_theta = std::clamp(cos_theta, 0.0, 1.0);
  const double cos2 = cos_theta * cos_theta, sin2 = 1.0 - cos2;
  const double t0 = n * n - k * k - sin2;
  const double a2_plus_b2 = std::sqrt(t0 * t0 + 4.0 * n * n * k * k);
  const double a = std::sqrt(std::max(0.0, 0.5 * (a2_plus_b2 + t0)));
  const double r_s_num = a2_plus_b2 - 2.0 * a * cos_theta + cos2;
  const double r_s_den = a2_plus_b2 + 2.0 * a * cos_theta + cos2;
  const double r_s = r_s_den > 0 ? r_s_num / r_s_den : 1.0;
  const double t1 = a2_plus_b2 * cos2 + sin2 * sin2, t2 = 2.0 * a * cos_theta * sin2;
  const double r_p = t1 + t2 > 0 ? r_s * (t1 - t2) / (t1 + t2) : 1.0;
  return 0.5 * (r_s + r_p);
}

}  // namespace brdf::gonio
