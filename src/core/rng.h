// The one random-number generator of every integrator: the albedo Monte Carlo, the virtual
// gonioreflectometer, the preview renderer and a fit's subsampling.
//
// Determinism whatever the thread count (DESIGN §5) comes from giving every unit of work (an
// incidence, a reading, a pixel, a traced ray) its own sequence, named by an index and never by
// the thread that happens to run it. The shape is pbrt-v4's `RNG(sequenceIndex, seed)`: a seed
// picks a family of streams, a sequence index one stream of it.
//
// The generator is SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number
// generators", OOPSLA 2014): one 64-bit state, a Weyl step by the golden gamma and a strong
// output mix, so that streams seeded from consecutive indices are independent. It passes
// BigCrush; one addition and a few multiplies per number.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/angles.h"
#include "core/sampling.h"

namespace brdf {

// The output mix (Stafford's variant 13 of MurmurHash3's finalizer), also used to derive seeds.
inline uint64_t SplitMix64Mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The sequence index of item `index` of a purpose (e.g. the noise of reading k, as against
// the jitter of reading k), so that streams of different purposes never coincide.
inline uint64_t SequenceIndex(uint64_t purpose, uint64_t index) {
  return SplitMix64Mix(purpose * 0xd1b54a32d192ed03ULL) + index;
}

class Rng {
 public:
  Rng() : Rng(0, 0) {}
  explicit Rng(uint64_t sequence_index, uint64_t seed = 0)
      : state_(SplitMix64Mix(seed) ^ SplitMix64Mix(~sequence_index)) {}

  // 64 random bits.
  uint64_t Bits() {
    state_ += 0x9e3779b97f4a7c15ULL;  // the golden gamma
    return SplitMix64Mix(state_);
  }
  // Uniform in [0, 1): the top 53 bits, so every value is exactly representable.
  double Uniform() { return static_cast<double>(Bits() >> 11) * 0x1.0p-53; }
  // Uniform in [0, 1), 24 random bits: every value a float holds exactly.
  float UniformFloat() { return static_cast<float>(Bits() >> 40) * 0x1.0p-24f; }
  Point2 Uniform2D() {
    const double u0 = Uniform();
    return Point2(u0, Uniform());
  }
  // Uniform in {0, ..., count - 1} for count >= 1; the modulo's bias is below count / 2^64.
  uint64_t Below(uint64_t count) { return Bits() % count; }
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
  uint64_t state_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace brdf
