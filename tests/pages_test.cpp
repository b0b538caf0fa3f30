// core/pages.h: PrefaultPages makes fresh pages resident and keeps the bytes; ReturnFreePages makes
// a freed block inside the heap stop counting as resident.
#include "core/pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
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

#if defined(__linux__)
// Resident pages of [data, data + bytes), from mincore.
size_t ResidentPages(void* data, size_t bytes) {
  const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  std::vector<unsigned char> resident((bytes + page - 1) / page);
  if (mincore(data, bytes, resident.data()) != 0) return 0;
  size_t count = 0;
  for (unsigned char flags : resident) count += flags & 1;
  return count;
}
#endif

TEST(Prefault, MakesFreshPagesResidentAndKeepsTheBytes) {
#if defined(__linux__)
  const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  const size_t bytes = 4096 * page;
  void* mapping = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(mapping, MAP_FAILED);
  unsigned char* data = static_cast<unsigned char*>(mapping);
  // A few pages already written, with bytes that must survive.
  for (size_t k = 0; k < bytes; k += 97 * page) data[k + 5] = static_cast<unsigned char>(k / page);
  ASSERT_LT(ResidentPages(data, bytes), bytes / page / 2);
  PrefaultPages(data, bytes);
  EXPECT_EQ(ResidentPages(data, bytes), bytes / page);
  for (size_t k = 0; k < bytes; k += page) {
    const unsigned char expected = k % (97 * page) == 0 ? static_cast<unsigned char>(k / page) : 0;
    ASSERT_EQ(data[k + 5], expected) << "page " << k / page;
  }
  munmap(mapping, bytes);
#else
  GTEST_SKIP() << "reads residency through mincore";
#endif
}

TEST(Prefault, ReservePrefaultedKeepsTheElementsAndReservesAtLeastTheCount) {
  std::vector<uint64_t> values(1000);
  for (size_t k = 0; k < values.size(); ++k) values[k] = k * k;
  ReservePrefaulted(&values, size_t{1} << 22);
  EXPECT_GE(values.capacity(), size_t{1} << 22);
  ASSERT_EQ(values.size(), 1000u);
  for (size_t k = 0; k < values.size(); ++k) ASSERT_EQ(values[k], k * k);
}

TEST(Prefault, AssignPrefaultedSizesTheBufferWithTheValue) {
  std::vector<double> values = {1.0, 2.0};
  AssignPrefaulted(&values, size_t{1} << 21, -0.5);
  ASSERT_EQ(values.size(), size_t{1} << 21);
  for (size_t k = 0; k < values.size(); k += 4099) ASSERT_EQ(values[k], -0.5) << k;
  EXPECT_EQ(values.back(), -0.5);
}

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
