// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA
// 2014): one 64-bit state, a Weyl step by the golden gamma and a strong output mix, so that
// streams seeded from consecutive indices are independent. The one generator of every
// integrator: the albedo Monte Carlo (energy/random.h), the virtual gonioreflectometer
// (gonio/rng.h) and the preview renderer (render/sampling.h) differ only in how they seed it.
#pragma once

#include <cstdint>

namespace brdf {

// The output mix (Stafford's variant 13 of MurmurHash3's finalizer), also used to derive seeds.
inline uint64_t SplitMix64Mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t state) : state_(state) {}
  uint64_t Next() {
    state_ += 0x9e3779b97f4a7c15ULL;  // the golden gamma
    return SplitMix64Mix(state_);
  }
  // Uniform in [0, 1): the top 53 bits, so every value is exactly representable.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

 private:
  uint64_t state_;
};

}  // namespace brdf
