#include "core/pages.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>  // also defines __GLIBC__ where the C library is glibc
#include <vector>

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
  // Memory reused from an earlier buffer (the heap keeps what `brdf` frees) is resident already:
  // asking the kernel which pages are costs far less than faulting them again, and the parts
  // that are whole are skipped.
  std::vector<unsigned char> resident((end - begin) / page);
  const bool known = mincore(reinterpret_cast<void*>(begin), end - begin, resident.data()) == 0;
  auto whole = [&](uintptr_t first, uintptr_t last) {
    return known && std::all_of(resident.begin() + (first - begin) / page,
                                resident.begin() + (last - begin) / page,
                                [](unsigned char flags) { return flags & 1; });
  };
  if (whole(begin, end)) return;
  tbb::parallel_for(uintptr_t{0}, parts, [&](uintptr_t part) {
    const uintptr_t first = begin + part * kPart;
    const uintptr_t last = std::min(end, first + kPart);
    if (whole(first, last)) return;
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
