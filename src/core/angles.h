// Frame and angle conventions (DESIGN §1), written once.
//
// Local shading frame: z is the surface normal, x the tangent at azimuth 0. Directions are
// unit vectors pointing *away* from the surface: wi toward the light, wo toward the detector.
// theta is the polar angle from +z, phi the azimuth from +x toward +y, both in radians.
#pragma once

#include <cmath>
#include <string>

#include "core/vec.h"

namespace brdf {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 1.0 / kPi;

inline constexpr double DegToRad(double deg) { return deg * (kPi / 180.0); }
inline constexpr double RadToDeg(double rad) { return rad * (180.0 / kPi); }

// Unit vector for polar angle theta and azimuth phi.
Vec3 SphericalDirection(double theta, double phi);

// Polar angle of a unit vector, in [0, pi]; robust near the poles (uses atan2, not acos).
double Theta(const Vec3& w);
// Azimuth of a unit vector in [0, 2*pi); 0 for a vector on the z axis.
double Phi(const Vec3& w);

// The polar angles of unit vector w in degrees, as the shortest decimal texts that read back
// (degrees -> DegToRad -> SphericalDirection) to exactly w: a direction made from 5 degrees
// prints "5", not the "4.999999999999999" that acos and a degree conversion give. A direction
// no decimal reproduces bit for bit (one made by jitter, say) prints the shortest text that reads
// back to its degree values.
struct DegreesText {
  std::string theta, phi;
};
DegreesText DirectionDegreesText(const Vec3& w);

template <typename T>
inline T CosTheta(const Vec3T<T>& w) {
  return w.z();
}

// Mirror direction of w about the normal: the specular reflection of an incident direction.
template <typename T>
inline Vec3T<T> MirrorDirection(const Vec3T<T>& w) {
  return Vec3T<T>(-w.x(), -w.y(), w.z());
}

// Rusinkiewicz (1998) half/difference angles. The half vector h = normalize(wi + wo) has
// polar angles (theta_h, phi_h); the difference vector is wi expressed in a frame where h is
// the pole: rotate wi by -phi_h about z, then by -theta_h about y.
struct HalfDiff {
  double theta_h = 0, phi_h = 0, theta_d = 0, phi_d = 0;
};
HalfDiff ToHalfDiff(const Vec3& wi, const Vec3& wo);
// Inverse of ToHalfDiff: wi = Rz(phi_h) Ry(theta_h) d, wo = 2 (wi.h) h - wi.
void FromHalfDiff(const HalfDiff& hd, Vec3* wi, Vec3* wo);

}  // namespace brdf
