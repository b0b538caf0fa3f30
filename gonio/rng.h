// Random numbers for the virtual gonioreflectometer. Determinism whatever the thread count
// (DESIGN §5) comes from giving every unit of work its own stream, derived from
// (seed, purpose, index) and never from the thread that happens to run it.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/angles.h"

namespace brdf::gonio {

// What a stream is for, so that e.g. the noise of reading k and the jitter of reading k are
// independent (and switching noise off leaves the jitter of a run unchanged).
enum class Stream : uint64_t {
  kIncidenceJitter = 1,
  kDetectorJitter = 2,
  kReadingNoise = 3,
  kReferenceNoise = 4,
  kRayBatch = 5,
  kHeightField = 6,
};

// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA
// 2014): a 64-bit state advanced by a Weyl sequence and a strong output mix. Small, fast and
// good enough for Monte Carlo; its value is that any 64-bit seed starts an independent stream.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  Rng(uint64_t seed, Stream stream, uint64_t index)
      : state_(Mix(Mix(seed ^ (static_cast<uint64_t>(stream) * 0xd1b54a32d192ed03ULL)) + index)) {}

  uint64_t NextU64() {
    state_ += 0x9e3779b97f4a7c15ULL;
    return Mix(state_);
  }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  // Standard normal by the Box-Muller transform; the second of each pair is kept for the next
  // call (half the logarithms and square roots).
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - Uniform();  // (0, 1]: log stays finite
    const double u2 = Uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(2.0 * kPi * u2);
    has_spare_ = true;
    return radius * std::cos(2.0 * kPi * u2);
  }
  // Poisson count with the given mean: Knuth's product method for small means, the normal
  // approximation (rounded, clamped at 0) above 30.
  double Poisson(double mean) {
    if (mean <= 0) return 0;
    if (mean > 30) return std::fmax(0.0, std::round(mean + std::sqrt(mean) * Normal()));
    const double limit = std::exp(-mean);
    double product = Uniform();
    int count = 0;
    while (product > limit) {
      product *= Uniform();
      ++count;
    }
    return count;
  }

 private:
  static uint64_t Mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  uint64_t state_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace brdf::gonio
