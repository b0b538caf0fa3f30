// Seeded random numbers that do not depend on the thread count: every independent piece of
// work (one incidence angle, one pixel) owns a stream derived from (seed, stream index), so
// the result is the same whichever thread runs it and in whatever order (DESIGN §5's rule,
// applied to every Monte Carlo estimate).
#pragma once

#include <cstdint>

#include "core/sampling.h"
#include "core/splitmix64.h"

namespace brdf {

// The shared SplitMix64 (core/splitmix64.h), keyed by (seed, stream). Passes BigCrush; one
// addition and a few multiplies per number.
class RandomStream {
 public:
  RandomStream(uint64_t seed, uint64_t stream)
      : generator_(SplitMix64Mix(seed) ^ SplitMix64Mix(~stream)) {}

  uint64_t NextBits() { return generator_.Next(); }
  // Uniform in [0, 1): the top 53 bits, so every value is exactly representable.
  double Uniform() { return generator_.Uniform(); }
  Point2 Uniform2D() {
    const double u0 = Uniform();
    return Point2(u0, Uniform());
  }

 private:
  SplitMix64 generator_;
};

}  // namespace brdf
