#include "core/angles.h"

namespace brdf {
namespace {

Vec3 RotateZ(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return Vec3(c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z());
}

Vec3 RotateY(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return Vec3(c * v.x() + s * v.z(), v.y(), -s * v.x() + c * v.z());
}

}  // namespace

Vec3 SphericalDirection(double theta, double phi) {
  const double sin_theta = std::sin(theta);
  return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), std::cos(theta));
}

double Theta(const Vec3& w) { return std::atan2(std::hypot(w.x(), w.y()), w.z()); }

double Phi(const Vec3& w) {
  if (w.x() == 0.0 && w.y() == 0.0) return 0.0;
  const double phi = std::atan2(w.y(), w.x());
  if (phi >= 0.0) return phi;
  // A tiny negative angle plus 2*pi rounds to exactly 2*pi; keep the promise of [0, 2*pi).
  const double wrapped = phi + 2.0 * kPi;
  return wrapped < 2.0 * kPi ? wrapped : 0.0;
}

HalfDiff ToHalfDiff(const Vec3& wi, const Vec3& wo) {
  const Vec3 half_vector = (wi + wo).normalized();
  HalfDiff hd;
  hd.theta_h = Theta(half_vector);
  hd.phi_h = Phi(half_vector);
  const Vec3 diff = RotateY(RotateZ(wi, -hd.phi_h), -hd.theta_h);
  hd.theta_d = Theta(diff);
  hd.phi_d = Phi(diff);
  return hd;
}

void FromHalfDiff(const HalfDiff& hd, Vec3* wi, Vec3* wo) {
  const Vec3 half_vector = SphericalDirection(hd.theta_h, hd.phi_h);
  const Vec3 diff = SphericalDirection(hd.theta_d, hd.phi_d);
  *wi = RotateZ(RotateY(diff, hd.theta_h), hd.phi_h);
  *wo = 2.0 * wi->dot(half_vector) * half_vector - *wi;
}

}  // namespace brdf
