// Large buffers' pages: backed by transparent huge pages, and handed back when freed.
//
// A MERL table's fit holds a few buffers of 30-120 MB, each written once from the start. With
// the kernel's 4 KiB pages every first touch of a page is a fault (the kernel zeroes and charges
// it): about 0.15 s of system time in a 1 s fit. Advised before their first touch, such buffers
// are faulted 2 MiB at a time. Linux with transparent huge pages in "madvise" or "always" mode;
// elsewhere, or for small buffers, nothing happens. Only the timing changes, never a value.
#pragma once

#include <cstddef>
#include <vector>

namespace brdf {

// Advises the whole 2 MiB regions inside [data, data + bytes) for huge pages. Call before the
// buffer is first written; a no-op below a few MiB, or where the system has no such advice.
void AdviseHugePages(const void* data, size_t bytes);

// reserve(count) with the reserved storage advised for huge pages (before any element is
// constructed, so before any page is touched).
template <typename T>
void ReserveHugePages(std::vector<T>* buffer, size_t count) {
  buffer->reserve(count);
  AdviseHugePages(buffer->data(), buffer->capacity() * sizeof(T));
}

// Hands the free pages of the heap back to the system (glibc's malloc_trim; elsewhere nothing).
// `brdf` keeps freed memory for reuse (src/cli/main.cpp); after it lets go of a large buffer
// that no later one of its size would reuse, this lowers the peak that follows.
void ReturnFreePages();

}  // namespace brdf
