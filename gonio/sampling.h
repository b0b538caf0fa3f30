// Direction sampling shared by the instrument and the samples: an orthonormal frame around a
// direction, uniform cones, the cosine-weighted hemisphere and small random rotations.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/vec.h"

namespace brdf::gonio {

// Orthonormal basis with `normal` as its third axis (Duff et al., "Building an Orthonormal
// Basis, Revisited", JCGT 6(1), 2017): branch-free and continuous except at normal.z = -0.
struct Frame {
  Vec3 tangent, bitangent, normal;

  explicit Frame(const Vec3& n) : normal(n) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    tangent = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    bitangent = Vec3(b, sign + n.y() * n.y() * a, -n.y());
  }
  Vec3 FromLocal(const Vec3& v) const {
    return v.x() * tangent + v.y() * bitangent + v.z() * normal;
  }
  Vec3 ToLocal(const Vec3& v) const {
    return Vec3(v.dot(tangent), v.dot(bitangent), v.dot(normal));
  }
};

// Cosine of the half-angle of a cone of solid angle `solid_angle`: Ω = 2π(1 − cos a).
inline double ConeCosHalfAngle(double solid_angle) { return 1.0 - solid_angle / (2.0 * kPi); }

// Direction in a cone of half-angle acos(cos_max) around +z, uniform in solid angle, from a
// point (u1, u2) of the unit square.
inline Vec3 SampleUniformCone(double u1, double u2, double cos_max) {
  const double cos_theta = 1.0 - u1 * (1.0 - cos_max);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * u2;
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

// Cosine-weighted direction on the hemisphere around +z (Malley's method: a uniform point of
// the unit disk lifted to the hemisphere); pdf = cos(theta)/π.
inline Vec3 SampleCosineHemisphere(double u1, double u2) {
  const double radius = std::sqrt(u1);
  const double phi = 2.0 * kPi * u2;
  const double x = radius * std::cos(phi), y = radius * std::sin(phi);
  return Vec3(x, y, std::sqrt(std::max(0.0, 1.0 - u1)));
}

// Rotates unit vector `w` by a small random angle: a 2D Gaussian offset of standard deviation
// `sigma` (radians) in the plane perpendicular to w, given two standard normal numbers.
inline Vec3 PerturbDirection(const Vec3& w, double sigma, double g1, double g2) {
  if (sigma <= 0) return w;
  const Frame frame(w);
  return (w + sigma * (g1 * frame.tangent + g2 * frame.bitangent)).normalized();
}

}  // namespace brdf::gonio
