// Random numbers of the preview renderer; the warps and frames it samples with are shared, in
// core/sampling.h.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/sampling.h"

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

}  // namespace brdf
