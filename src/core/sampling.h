// Warps from the unit square to directions, each with its pdf (in solid angle), and the frames
// they need, written once for every integrator: the albedo estimators, the virtual
// gonioreflectometer and the preview renderer.
// Families follow pbrt-v4's naming (Pharr, Jakob & Humphreys, PBR 4th ed., §A.5): SampleX maps
// u in [0,1)^2 to a direction, XPdf is the density of that direction.
//
// Directions are unit vectors in the local frame of DESIGN §1 (z = normal) unless a function
// says it works around another axis.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/vec.h"

namespace brdf {

// A point of the unit square: the random (or quadrature) numbers a warp consumes.
using Point2 = Eigen::Vector2d;

// Cosine-weighted hemisphere by the polar map: r = sqrt(u0), phi = 2 pi u1 (Malley's method:
// uniform on the disk, projected up). pdf = cos(theta) / pi, so that f cos / pdf = pi f.
// The polar (not concentric) map is used because it is smooth in u, which lets the same warp
// serve deterministic quadrature as well as Monte Carlo.
inline Vec3 SampleCosineHemisphere(const Point2& u) {
  const double radius = std::sqrt(u.x());
  const double phi = 2.0 * kPi * u.y();
  return Vec3(radius * std::cos(phi), radius * std::sin(phi), std::sqrt(std::max(0.0, 1 - u.x())));
}
inline double CosineHemispherePdf(double cos_theta) {
  return cos_theta > 0.0 ? cos_theta * kInvPi : 0.0;
}

// Power-cosine lobe about +z: pdf = (e+1)/(2 pi) cos^e(theta) on the hemisphere. Inverting its
// CDF gives cos(theta) = u0^(1/(e+1)) (Shirley & Chiu style warp; pbrt-v3 §14.1.2 uses the
// same density for the Phong lobe). e = 1 is the cosine-weighted hemisphere.
inline double PowerCosineLobeCosTheta(double u0, double exponent) {
  return std::pow(u0, 1.0 / (exponent + 1.0));
}
inline Vec3 SamplePowerCosineLobe(const Point2& u, double exponent) {
  const double cos_theta = PowerCosineLobeCosTheta(u.x(), exponent);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * u.y();
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}
inline double PowerCosineLobePdf(double cos_theta, double exponent) {
  if (cos_theta <= 0.0) return 0.0;
  return (exponent + 1.0) * (0.5 * kInvPi) * std::pow(cos_theta, exponent);
}

// An orthonormal frame whose z axis is a given unit vector (Duff et al., "Building an
// Orthonormal Basis, Revisited", JCGT 6(1), 2017: branchless and exact at the poles).
struct Frame {
  Vec3 x, y, z;

  static Frame FromZ(const Vec3& z) {
    const double sign = std::copysign(1.0, z.z());
    const double a = -1.0 / (sign + z.z());
    const double b = z.x() * z.y() * a;
    return {Vec3(1.0 + sign * z.x() * z.x() * a, sign * b, -sign * z.x()),
            Vec3(b, sign + z.y() * z.y() * a, -z.y()), z};
  }
  Vec3 FromLocal(const Vec3& v) const { return v.x() * x + v.y() * y + v.z() * z; }
  Vec3 ToLocal(const Vec3& v) const { return Vec3(v.dot(x), v.dot(y), v.dot(z)); }
};

// A cone of solid angle `solid_angle` around an axis has cos(half-angle) = 1 - Ω/(2π).
inline double ConeCosHalfAngle(double solid_angle) { return 1.0 - solid_angle / (2.0 * kPi); }

// Uniform in solid angle inside the cone of half-angle acos(cos_max) around +z;
// pdf = 1 / (2π (1 - cos_max)).
inline Vec3 SampleUniformCone(const Point2& u, double cos_max) {
  const double cos_theta = 1.0 - u.x() * (1.0 - cos_max);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * u.y();
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

// The direction w reflected about the unit vector n: 2 (w.n) n - w. With n = the half vector,
// it maps wo to the wi whose half vector is n.
inline Vec3 Reflect(const Vec3& w, const Vec3& n) { return 2.0 * w.dot(n) * n - w; }

// Density of wi = Reflect(wo, h) when h is drawn with density pdf_h: the half-vector Jacobian
// dω_h / dω_i = 1 / (4 (wo.h)) (Torrance & Sparrow 1967; Walter et al., EGSR 2007, eq. 14).
inline double HalfVectorToIncidentPdf(double pdf_h, double wo_dot_h) {
  return wo_dot_h > 0.0 ? pdf_h / (4.0 * wo_dot_h) : 0.0;
}

}  // namespace brdf
