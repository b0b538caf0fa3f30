// Random numbers for the virtual gonioreflectometer. Determinism whatever the thread count
// (DESIGN §5) comes from giving every unit of work its own stream, derived from
// (seed, purpose, index) and never from the thread that happens to run it.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/angles.h"
#include "core/splitmix64.h"

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
  kRayPath = 7,  // one traced path: (incidence seed, ray index)
};

// The shared SplitMix64 (core/splitmix64.h), seeded by (seed, purpose, index): any 64-bit seed
// starts an independent stream; normal and Poisson draws on top of it.
class Rng {
 public:
  explicit Rng(uint64_t seed) : generator_(seed) {}
  Rng(uint64_t seed, Stream stream, uint64_t index)
      : generator_(SplitMix64Mix(
            SplitMix64Mix(seed ^ (static_cast<uint64_t>(stream) * 0xd1b54a32d192ed03ULL)) +
            index)) {}

  uint64_t NextU64() { return generator_.Next(); }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return generator_.Uniform(); }
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
  SplitMix64 generator_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace brdf::gonio
