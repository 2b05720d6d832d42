#include "tc/core/heap.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace tc::core {

void release_free_heap(double at_least) {
#if defined(__GLIBC__)
  // fordblks: the free bytes in the heaps' chunks (mmapped blocks are returned on free), of
  // which keepcost is the top's. The top is left as it is (malloc_trim keeps that much there):
  // it may be the pad of core's heap policy (petsc.cpp, prefer_huge_pages), untouched pages.
  const auto info = mallinfo2();
  if (static_cast<double>(info.fordblks - info.keepcost) < at_least) return;
  (void)malloc_trim(info.keepcost);
#else
  (void)at_least;
#endif
}

}  // namespace tc::core
