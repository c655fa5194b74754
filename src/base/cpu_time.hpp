// The CPU time of the calling thread: what it computed, without the time it waited for the
// processor (another process on its core, a virtual machine's stolen time), which wall time
// counts. A decomposed domain weighs its ranks' work with it (domain/slab_rebalance.cpp).
#pragma once

#include <time.h>

namespace geodem {

inline double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace geodem
