// ReturnFreePages (core/pages.h): a freed block inside the heap stops counting as resident.
#include "core/pages.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <unistd.h>
#endif

// AddressSanitizer brings its own allocator, which glibc's malloc_trim does not reach.
#if defined(__SANITIZE_ADDRESS__)
#define BRDFKIT_OWN_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define BRDFKIT_OWN_ALLOCATOR 1
#endif
#endif

namespace brdf {
namespace {

#if defined(__linux__) && defined(__GLIBC__) && !defined(BRDFKIT_OWN_ALLOCATOR)
// Resident bytes of this process: the second field of /proc/self/statm, in pages.
long ResidentBytes() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return resident * sysconf(_SC_PAGESIZE);
}

// Keeps the compiler from dropping writes to, or the allocation of, `p`.
void Escape(void* p) { asm volatile("" : : "g"(p) : "memory"); }
#endif

TEST(FreePages, HandsAFreedHeapBlockBack) {
#if defined(__linux__) && defined(__GLIBC__) && !defined(BRDFKIT_OWN_ALLOCATOR)
  // As `brdf` sets them (src/cli/main.cpp): large blocks come from the heap and stay there when
  // freed, so only ReturnFreePages gives their pages back.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  constexpr size_t kBlock = size_t{64} << 20;
  auto block = std::make_unique<char[]>(kBlock);
  // A later block keeps the first from lying at the heap's top, where free alone would shrink it.
  auto guard = std::make_unique<char[]>(size_t{1} << 20);
  std::memset(block.get(), 1, kBlock);
  std::memset(guard.get(), 1, size_t{1} << 20);
  Escape(block.get());
  Escape(guard.get());
  block.reset();
  const long before = ResidentBytes();
  ReturnFreePages();
  const long after = ResidentBytes();
  EXPECT_GT(before - after, static_cast<long>(kBlock / 2))
      << "resident " << before << " bytes before, " << after << " after";
  Escape(guard.get());
#else
  GTEST_SKIP() << "measures resident pages through /proc and glibc's malloc_trim (not under "
                  "AddressSanitizer's allocator)";
#endif
}

}  // namespace
}  // namespace brdf
