#include "core/free_pages.h"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace brdf {

void ReturnFreePages() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace brdf
