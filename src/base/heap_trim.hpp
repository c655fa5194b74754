// Freed memory back to the system. glibc keeps the blocks freed inside its heap resident
// (only the heap's top is given back); large arrays land in such holes too when one is free
// (its threshold for pages of their own is only taken when the heap has no fitting hole), so
// that giving an array back before a list build did not lower the build's peak
// (docs/performance.md, "Memory").
#pragma once

// (not under AddressSanitizer: its allocator is not glibc's, and glibc's trim of arenas that
// allocator does not keep crashed when ranks as threads trimmed at once)
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#include <malloc.h>
#define GEODEM_TRIM_HEAP 1
#endif

namespace geodem {

// Gives the free pages of every malloc arena back to the system; a no-op elsewhere.
inline void give_free_heap_back() {
#ifdef GEODEM_TRIM_HEAP
  malloc_trim(0);
#endif
}

}  // namespace geodem
