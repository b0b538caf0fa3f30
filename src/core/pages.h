// The pages of large buffers: fresh pages faulted in ahead of use, from every core at once;
// huge pages for a table read at random; and freed heap pages handed back to the system.
//
// A fresh page is costly on a virtual machine: the guest faults it in, and the host then
// supplies and clears the memory behind it on its first access. On the 2-core virtual machine
// of docs/performance.md (*Fresh pages*, bench/page_cost) a first write to each 4 KiB page of a
// new 128 MiB block cost 2.6 ms per MiB on one thread; MADV_POPULATE_WRITE (one call for the
// range, no fault per page) followed by the first access 1.3 ms, and both on two threads
// (PrefaultPages) 0.71-0.76 ms per MiB of wall time. A MERL-table fit faults about 250 MB, so a
// serial first touch of its buffers took about half of its time.
//
// Only a table whose reads land anywhere in it is advised for transparent huge pages: with 4 KiB
// pages nearly every read of the renderer's 12.6 MB environment table also missed the TLB (the
// renders took 2-5 % longer without the advice; docs/performance.md, *Huge pages*). Buffers written
// once from the start and then streamed, as a fit's are, are not: on a virtual machine whose
// balloon reports free memory to the host (order-9 blocks, Linux's free page reporting), every
// fresh huge page is one the host has taken back, and a MERL-table fit started two seconds after
// the last large process spent 0.8 s of system time faulting its 250 MB (1.25 s in all, against
// 0.62 s without the advice; docs/performance.md, *Huge pages*). Only the timing changes, never a
// value.
#pragma once

#include <cstddef>
#include <vector>

namespace brdf {

// Advises the whole 2 MiB regions inside [data, data + bytes) for huge pages: a no-op below a
// few MiB, or where the system has no such advice.
void AdviseHugePages(const void* data, size_t bytes);

// Faults in the pages of [data, data + bytes) ahead of use, split across the worker threads: each
// part is populated for writing in one call (MADV_POPULATE_WRITE, where the kernel has it) and
// then read and written back once a page, so that no loop after it meets a fresh page. The bytes
// are unchanged. A no-op for less than a few pages.
void PrefaultPages(void* data, size_t bytes);

// reserve(count) with the storage not yet holding elements faulted in (PrefaultPages): the
// elements then constructed, serially or not, land on pages already there.
template <typename T>
void ReservePrefaulted(std::vector<T>* buffer, size_t count) {
  buffer->reserve(count);
  T* unused = buffer->data() + buffer->size();
  PrefaultPages(unused, (buffer->capacity() - buffer->size()) * sizeof(T));
}

// A buffer sized to `count` copies of `value` on pages faulted in from every core first
// (ReservePrefaulted): the fill, on one thread, meets no fresh page.
template <typename T>
void AssignPrefaulted(std::vector<T>* buffer, size_t count, const T& value = T()) {
  ReservePrefaulted(buffer, count);
  buffer->assign(count, value);
}

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
