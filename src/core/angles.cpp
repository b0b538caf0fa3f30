#include "core/angles.h"

#include <algorithm>
#include <charconv>

#include "core/text.h"

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

// The number `text` reads as (it always parses: FormatNumber wrote it).
double ReadBack(const std::string& text) {
  double value = 0;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

// Digits a schedule's angles carry (22.5, 7.07107 are as long as they get); beyond them the
// shortest round trip of the degree value is as short as the text can be.
constexpr int kScheduleDigits = 6;
// A degree value made from such an angle is off it by a few units in the last place (acos and
// two conversions); farther than this, no short text can reproduce the direction.
constexpr double kNearShort = 1e-12;

// The shortest of FormatNumber(value, 1..kScheduleDigits) for which `reproduces` holds, else the
// shortest round trip of `value` itself. The search runs only when `value` lies within
// kNearShort of its kScheduleDigits rounding, so an arbitrary angle costs one extra formatting.
template <typename Reproduces>
std::string ShortestReproducing(double value, const Reproduces& reproduces) {
  const double rounded = ReadBack(FormatNumber(value, kScheduleDigits));
  if (std::abs(rounded - value) <= kNearShort * std::max(1.0, std::abs(value))) {
    for (int significant = 1; significant <= kScheduleDigits; ++significant) {
      // Rounded to `significant` digits, then written the shortest way (10, not 1e+01).
      const double candidate = ReadBack(FormatNumber(value, significant));
      if (reproduces(candidate)) return FormatNumber(candidate);
    }
  }
  return FormatNumber(value);
}

}  // namespace

DegreesText DirectionDegreesText(const Vec3& w) {
  const double theta_deg = RadToDeg(Theta(w)), phi_deg = RadToDeg(Phi(w));
  DegreesText text;
  // z depends on theta alone, so theta is settled first, then phi against the whole vector.
  text.theta = ShortestReproducing(
      theta_deg, [&](double theta) { return std::cos(DegToRad(theta)) == w.z(); });
  const double theta = DegToRad(ReadBack(text.theta));
  text.phi = ShortestReproducing(
      phi_deg, [&](double phi) { return SphericalDirection(theta, DegToRad(phi)) == w; });
  return text;
}

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
