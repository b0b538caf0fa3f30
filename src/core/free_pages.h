// Freed heap pages handed back to the system.
//
// Large buffers are not advised for transparent huge pages: on a virtual machine whose balloon
// reports free memory to the host (order-9 blocks, Linux's free page reporting), every fresh
// huge page is one the host has taken back, and a `brdf fit` of a MERL table started more than
// two seconds after the last large process spent 0.8 s of system time faulting its 250 MB
// (1.25 s in all, against 0.62 s without the advice; docs/performance.md, *Huge pages*).
#pragma once

namespace brdf {

// Hands the free pages of the heap back to the system (glibc's malloc_trim; elsewhere nothing).
// `brdf` keeps freed memory for reuse (src/cli/main.cpp); after it lets go of a large buffer
// that no later one of its size would reuse, this lowers the peak that follows.
void ReturnFreePages();

}  // namespace brdf
