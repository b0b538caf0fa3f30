// ggx: f = rho_d/π + F(wi·h) D(h) G2(wi, wo) / (4 cos theta_i cos theta_o), the microfacet model
// of microfacet.h with the Trowbridge-Reitz distribution (Trowbridge & Reitz 1975; named GGX by
// Walter, Marschner, Li & Torrance, "Microfacet models for refraction through rough surfaces",
// EGSR 2007):
//   D(h) = α² / (π (cos²theta_h (α² − 1) + 1)²),
//   Λ(w) = (−1 + sqrt(1 + α² tan²theta)) / 2.
//
// Parameters: rho_d (RGB, default 0.5), f0 (RGB in [0, 1], default 0.04), alpha (default 0.1).
// Example: `ggx:rho_d=0.2,0.05,0.05:f0=0.04:alpha=0.08`.
//
// D's tails fall as tan^-4(theta_h), far slower than Beckmann's Gaussian: a glossy coating's
// haze. ∫ D cos(theta_h) dω_h = 1 (the tests check it), so D cos(theta_h) is a density of half
// vectors, and its CDF in theta_h is tan²/(α² + tan²): the samplers invert it.
#pragma once

#include <Eigen/Geometry>

#include "models/microfacet.h"

namespace brdf::models {

struct Ggx : MicrofacetModel<Ggx> {
  static constexpr const char* kName = "ggx";
  static constexpr const char* kFormula =
      "rho_d/pi + F D G2 / (4 cos_i cos_o); D = a^2/(pi (cos^2 h (a^2-1)+1)^2), Schlick F, "
      "height-correlated Smith G2";

  template <typename T, typename Dir>
  static T D(const Dir& cos_theta_h, const T& alpha) {
    const T alpha2 = alpha * alpha;
    const T denominator = T(cos_theta_h * cos_theta_h) * (alpha2 - T(1)) + T(1);
    return alpha2 / (T(kPi) * denominator * denominator);
  }

  template <typename T, typename Dir>
  static T Lambda(const Dir& cos_theta, const T& alpha) {
    using std::sqrt;
    return (sqrt(T(1) + alpha * alpha * T(TanSquared(cos_theta))) - T(1)) * T(0.5);
  }

  // The half-vector density D cos(theta_h): mass beyond theta_h is α²/(α² + tan²theta_h).
  static double MassBeyond(double cos_h, double alpha) {
    const double a2c2 = alpha * alpha * cos_h * cos_h;
    return a2c2 / (a2c2 + 1.0 - cos_h * cos_h);
  }
  static double CosAt(double u, double alpha) {
    return std::sqrt(u / (u + alpha * alpha * (1.0 - u)));
  }
  static double Density(double cos_h, double alpha) { return D(cos_h, alpha) * cos_h; }

  // The normals visible from wo, D_wo(h) = G1(wo) max(0, wo.h) D(h) / cos(theta_o), sampled
  // after Heitz, "Sampling the GGX distribution of visible normals", JCGT 7(4), 2018: stretch
  // wo to the configuration where alpha = 1 (there the visible normals are a hemisphere seen
  // from wo), draw a point on the projected disk with the part hidden behind the hemisphere's
  // rim folded onto the visible part, lift it to the hemisphere and unstretch the normal.
  static Vec3 SampleVisibleNormal(const Vec3& wo, double u0, double u1, double alpha) {
    const Vec3 view = Vec3(alpha * wo.x(), alpha * wo.y(), wo.z()).normalized();
    const double length2 = view.x() * view.x() + view.y() * view.y();
    const Vec3 t1 =
        length2 > 0 ? Vec3(-view.y(), view.x(), 0.0) / std::sqrt(length2) : Vec3(1, 0, 0);
    const Vec3 t2 = view.cross(t1);
    const double radius = std::sqrt(u0), phi = 2.0 * kPi * u1;
    const double p1 = radius * std::cos(phi);
    const double blend = 0.5 * (1.0 + view.z());
    const double p2 =
        (1.0 - blend) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + blend * radius * std::sin(phi);
    const Vec3 normal =
        p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * view;
    return Vec3(alpha * normal.x(), alpha * normal.y(), std::max(0.0, normal.z())).normalized();
  }
  static double VisibleNormalDensity(const Vec3& wo, const Vec3& h, double alpha) {
    const double wo_dot_h = wo.dot(h);
    if (!(wo.z() > 0.0) || !(h.z() > 0.0) || !(wo_dot_h > 0.0)) return 0.0;
    return D(h.z(), alpha) * wo_dot_h / ((1.0 + Lambda(wo.z(), alpha)) * wo.z());
  }
  static constexpr LobeDistribution kLobeDistribution = {
      "ggx", MassBeyond, CosAt, Density, SampleVisibleNormal, VisibleNormalDensity};

  // D falls to half its peak at tan²theta_h = (√2 − 1) α², where cos^e does for
  // e = 2 ln 2 / ((√2 − 1) α²).
  static double AlphaEquivalentExponent(double alpha) {
    return 2.0 * std::log(2.0) / ((std::sqrt(2.0) - 1.0) * alpha * alpha);
  }
};

}  // namespace brdf::models
