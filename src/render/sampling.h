// Random numbers of the preview renderer; the warps and frames it samples with are shared, in
// core/sampling.h.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/sampling.h"
#include "core/splitmix64.h"

namespace brdf {

// The shared SplitMix64 (core/splitmix64.h), seeded per pixel: streams seeded from
// consecutive pixel indices are independent, and one stream per pixel keeps a render the same
// whatever the number of threads.
class PixelRandom {
 public:
  PixelRandom(uint64_t seed, uint64_t pixel)
      : generator_(SplitMix64Mix(seed ^ SplitMix64Mix(pixel + 1))) {}
  // Uniform in [0, 1), 53 random bits.
  double Uniform() { return generator_.Uniform(); }
  // Uniform in [0, 1), 24 random bits: every value a float holds exactly (the hot loop's warps
  // are in float, core/float_math.h).
  float UniformFloat() { return static_cast<float>(generator_.Next() >> 40) * 0x1.0p-24f; }
  // 64 random bits, for a draw that needs more than a float's resolution (an environment pixel
  // out of millions, and the point inside it).
  uint64_t Bits() { return generator_.Next(); }

 private:
  SplitMix64 generator_;
};

}  // namespace brdf
