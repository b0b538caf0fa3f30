// The purposes of the virtual gonioreflectometer's random streams. Every unit of work draws
// from its own stream of the one generator (core/rng.h), named by (purpose, index) and never
// by the thread that runs it, so that e.g. the noise of reading k and the jitter of reading k
// are independent (and switching noise off leaves the jitter of a run unchanged).
#pragma once

#include <cstdint>

#include "core/rng.h"

namespace brdf::gonio {

enum class Stream : uint64_t {
  kIncidenceJitter = 1,
  kDetectorJitter = 2,
  kReadingNoise = 3,
  kReferenceNoise = 4,
  kRayBatch = 5,
  kHeightField = 6,
  kRayPath = 7,  // one traced path: (incidence seed, ray index)
};

// The stream of item `index` of a purpose, in the family of streams `seed` picks.
inline Rng StreamRng(uint64_t seed, Stream stream, uint64_t index) {
  return Rng(SequenceIndex(static_cast<uint64_t>(stream), index), seed);
}

}  // namespace brdf::gonio
