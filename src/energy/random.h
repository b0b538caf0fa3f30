// Seeded random numbers that do not depend on the thread count: every independent piece of
// work (one incidence angle, one pixel) owns a stream derived from (seed, stream index), so
// the result is the same whichever thread runs it and in whatever order (DESIGN §5's rule,
// applied to every Monte Carlo estimate).
#pragma once

#include <cstdint>

#include "core/sampling.h"

namespace brdf {

// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA
// 2014): a 64-bit counter stepped by the golden-ratio increment, then mixed. Passes BigCrush;
// one addition and a few multiplies per number.
class RandomStream {
 public:
  RandomStream(uint64_t seed, uint64_t stream) : state_(Mix(seed) ^ Mix(~stream)) {}

  uint64_t NextBits() {
    state_ += kGoldenGamma;
    return Mix(state_);
  }
  // Uniform in [0, 1): the top 53 bits, so every value is exactly representable.
  double Uniform() { return static_cast<double>(NextBits() >> 11) * 0x1.0p-53; }
  Point2 Uniform2D() {
    const double u0 = Uniform();
    return Point2(u0, Uniform());
  }

 private:
  static constexpr uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ULL;
  static uint64_t Mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  uint64_t state_;
};

}  // namespace brdf
