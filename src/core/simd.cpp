#include "core/simd.h"

#include <atomic>

namespace brdf {
namespace {

bool ProcessorHasAvx2() {
#if BRDF_HAS_AVX2_PATHS
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

std::atomic<bool>& Avx2Flag() {
  static std::atomic<bool> flag{ProcessorHasAvx2()};
  return flag;
}

}  // namespace

bool Avx2Enabled() { return Avx2Flag().load(std::memory_order_relaxed); }

bool SetAvx2Enabled(bool enabled) {
  return Avx2Flag().exchange(enabled && ProcessorHasAvx2(), std::memory_order_relaxed);
}

}  // namespace brdf
