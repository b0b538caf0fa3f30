#include "core/pages.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>  // also defines __GLIBC__ where the C library is glibc

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace brdf {

void AdviseHugePages(const void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHugePage = uintptr_t{1} << 21;
  if (data == nullptr || bytes < 2 * kHugePage) return;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHugePage - 1) & ~(kHugePage - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHugePage - 1);
  // Advice only: a kernel without transparent huge pages refuses it, and nothing changes.
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

void PrefaultPages(void* data, size_t bytes) {
#if defined(__linux__)
  static const uintptr_t page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  // Parts of 1 MiB: enough for both threads of a 250 MB fit's buffers to stay busy, few enough
  // calls that the system calls themselves do not show.
  constexpr uintptr_t kPart = uintptr_t{1} << 20;
  if (data == nullptr || bytes < 16 * page) return;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + page - 1) & ~(page - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(page - 1);
  if (end <= begin) return;
  const uintptr_t parts = (end - begin + kPart - 1) / kPart;
  tbb::parallel_for(uintptr_t{0}, parts, [&](uintptr_t part) {
    const uintptr_t first = begin + part * kPart;
    const uintptr_t last = std::min(end, first + kPart);
#if defined(MADV_POPULATE_WRITE)
    // Advice only: an older kernel refuses it, and the loop below faults the pages in instead.
    madvise(reinterpret_cast<void*>(first), last - first, MADV_POPULATE_WRITE);
#endif
    // The first access is what makes the host supply the page: one a page, the value kept.
    for (uintptr_t address = first; address < last; address += page) {
      volatile char* byte = reinterpret_cast<volatile char*>(address);
      *byte = *byte;
    }
  });
#else
  (void)data;
  (void)bytes;
#endif
}

void ReturnFreePages() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace brdf
