// Shared-memory parallelism of the step (OpenMP) under one rule: a result never depends
// on the number of threads. Loops whose iterations write only their own items run as
// plain parallel loops; sums are taken in fixed blocks whose partial results are added
// in block order; maxima and minima are exact in any order. The contact forces, which
// write to both grains of a pair, use the slab colouring of contacts/contact_forces.cpp.
// A run with 1 thread and one with 8 therefore give bit-identical histories
// (tests/unit/thread_determinism_test.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace geodem {

// Loops shorter than this run on the calling thread: a parallel region costs a few
// microseconds, the work of a few thousand grains.
constexpr std::size_t kParallelMin = 4096;

// Block length of ordered sums: fixed, so that the partial sums are the same whatever
// the thread count.
constexpr std::size_t kSumBlock = 2048;

// Sum of term(i) for i in [0, n), computed in blocks of kSumBlock on up to `threads`
// threads and added in block order: the same bits for any thread count.
template <typename T, typename Term>
T ordered_sum(std::size_t n, int threads, const T& zero, Term&& term) {
  const std::size_t blocks = (n + kSumBlock - 1) / kSumBlock;
  if (blocks <= 1) {
    T s = zero;
    for (std::size_t i = 0; i < n; ++i) s += term(i);
    return s;
  }
  static thread_local std::vector<T> parts;  // this caller's; reached below by pointer
  parts.assign(blocks, zero);
  T* part = parts.data();
  const auto nb = static_cast<std::ptrdiff_t>(blocks);
#pragma omp parallel for num_threads(threads) schedule(static) if (n >= kParallelMin)
  for (std::ptrdiff_t b = 0; b < nb; ++b) {
    const std::size_t lo = static_cast<std::size_t>(b) * kSumBlock;
    const std::size_t hi = lo + kSumBlock < n ? lo + kSumBlock : n;
    T s = zero;
    for (std::size_t i = lo; i < hi; ++i) s += term(i);
    part[static_cast<std::size_t>(b)] = s;
  }
  T total = zero;
  for (std::size_t b = 0; b < blocks; ++b) total += part[b];
  return total;
}

// Slabs: fixed ranges of grain indices that stages writing to both grains of a pair run
// side by side (contacts/contact_forces.cpp). Their length depends on the grain count
// alone, never on the thread count: long enough that few pairs cross slabs and that a
// slab's work (about 100 us for 1,024 grains) dwarfs the cost of handing it to a thread,
// short enough for 32 slabs to share among threads.
constexpr std::size_t kMinSlab = 1024;
inline std::size_t slab_length(std::size_t n) {
  return std::max<std::size_t>(kMinSlab, (n + 31) / 32);
}
inline std::size_t slab_count(std::size_t n) {
  return (n + slab_length(n) - 1) / slab_length(n);
}

// Runs body(slab, first, last) for every slab of n grains, side by side.
template <typename Body>
void for_slabs(std::size_t n, int threads, Body&& body) {
  const std::size_t len = slab_length(n);
  const auto ns = static_cast<std::ptrdiff_t>(slab_count(n));
  const bool par = threads > 1 && ns >= 2 && n >= kParallelMin;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1) if (par)
  for (std::ptrdiff_t s = 0; s < ns; ++s) {
    const std::size_t first = static_cast<std::size_t>(s) * len;
    body(static_cast<std::size_t>(s), first, std::min(n, first + len));
  }
}

// Threads of a run when none is asked for: GEODEM_THREADS, else OMP_NUM_THREADS, else 1
// (a run then never competes with the runs of a study or of a test suite for cores).
int default_threads();

// Whether the engine was built with OpenMP (else every loop runs on one thread).
bool built_with_openmp();

}  // namespace geodem
