// Random numbers and the sampling routines of the preview renderer.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/angles.h"
#include "core/vec.h"

namespace brdf {

// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators",
// OOPSLA 2014): one 64-bit state, a Weyl step and a strong output mix, so that streams seeded
// from consecutive pixel indices are independent. One stream per pixel keeps a render the
// same whatever the number of threads.
class PixelRandom {
 public:
  PixelRandom(uint64_t seed, uint64_t pixel) : state_(Mix(seed ^ Mix(pixel + 1))) {}
  // Uniform in [0, 1), 53 random bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

 private:
  static uint64_t Mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  uint64_t Next() {
    state_ += 0x9e3779b97f4a7c15ull;
    return Mix(state_);
  }
  uint64_t state_;
};

// Cosine-weighted direction on the hemisphere around +z (Malley's method: a uniform point on
// the unit disc lifted to the hemisphere), pdf cos(theta) / pi.
inline Vec3 SampleCosineHemisphere(double u1, double u2) {
  const double radius = std::sqrt(u1), phi = 2.0 * kPi * u2;
  const double x = radius * std::cos(phi), y = radius * std::sin(phi);
  return Vec3(x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y)));
}
inline double CosineHemispherePdf(double cos_theta) {
  return cos_theta > 0.0 ? cos_theta * kInvPi : 0.0;
}

// Tangent frame around a unit normal n (Duff et al., "Building an orthonormal basis,
// revisited", JCGT 6(1), 2017): no branch on a near-axis normal, continuous except at
// n.z = -1 exactly. Columns: tangent (local x), bitangent (local y), normal (local z).
struct ShadingFrame {
  Vec3 tangent, bitangent, normal;
  explicit ShadingFrame(const Vec3& n) : normal(n) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    tangent = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    bitangent = Vec3(b, sign + n.y() * n.y() * a, -n.y());
  }
  Vec3 ToLocal(const Vec3& world) const {
    return Vec3(world.dot(tangent), world.dot(bitangent), world.dot(normal));
  }
  Vec3 ToWorld(const Vec3& local) const {
    return local.x() * tangent + local.y() * bitangent + local.z() * normal;
  }
};

}  // namespace brdf
