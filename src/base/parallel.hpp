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
// A caller may fix the length instead (`fixed` > 0: World::fixed_slab).
constexpr std::size_t kMinSlab = 1024;
inline std::size_t slab_length(std::size_t n, std::size_t fixed = 0) {
  return fixed > 0 ? fixed : std::max<std::size_t>(kMinSlab, (n + 31) / 32);
}
inline std::size_t slab_count(std::size_t n, std::size_t fixed = 0) {
  return (n + slab_length(n, fixed) - 1) / slab_length(n, fixed);
}

// Runs body(slab, first, last) for every slab of n grains, side by side.
template <typename Body>
void for_slabs(std::size_t n, int threads, Body&& body, std::size_t fixed = 0) {
  const std::size_t len = slab_length(n, fixed);
  const auto ns = static_cast<std::ptrdiff_t>(slab_count(n, fixed));
  const bool par = threads > 1 && ns >= 2 && n >= kParallelMin;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1) if (par)
  for (std::ptrdiff_t s = 0; s < ns; ++s) {
    const std::size_t first = static_cast<std::size_t>(s) * len;
    body(static_cast<std::size_t>(s), first, std::min(n, first + len));
  }
}

// Contributions that the task of one slab computes for bodies outside it (grains of later
// slabs, or bodies numbered from n up: clumps), kept per source slab in one bucket per
// target slab. apply() then adds them with the target slabs side by side, each target's
// entries in (source slab, entry) order: every body receives its contributions in the same
// order as if all were added serially slab by slab, whatever the thread count. (Adding them
// serially cost a third of the force stage's time on two threads where many pairs cross
// slabs, as in a wide, flat bed.)
template <typename Entry>  // an Entry has a field `body`
class SlabCrossings {
 public:
  // Buckets for n grains; their contents are left to the slabs' tasks to clear.
  void prepare(std::size_t n, std::size_t fixed = 0) {
    n_ = n;
    len_ = slab_length(n, fixed);
    slabs_ = slab_count(n, fixed);
    if (buckets_.size() < slabs_ * (slabs_ + 1)) buckets_.resize(slabs_ * (slabs_ + 1));
  }
  // Where the task of slab s writes: emptied here, filled by push().
  class Writer {
   public:
    void push(const Entry& e) {
      // Most crossing pairs reach the next slab: spared the division.
      const std::size_t b = e.body;
      const std::size_t target = b >= n_ ? slabs_ : b - next_first_ < len_ ? next_ : b / len_;
      bucket_[target].push_back(e);
    }

   private:
    friend class SlabCrossings;
    std::vector<Entry>* bucket_;
    std::size_t n_, len_, slabs_;
    std::size_t next_, next_first_;  // the slab after the writer's, and its first body
  };
  Writer slab(std::size_t s) {
    Writer w;
    w.bucket_ = buckets_.data() + s * (slabs_ + 1);
    for (std::size_t t = 0; t <= slabs_; ++t) w.bucket_[t].clear();
    w.n_ = n_, w.len_ = len_, w.slabs_ = slabs_;
    // For the last slab next_first_ >= n_: no grain maps there, bodies from n_ up go to slabs_.
    w.next_ = s + 1;
    w.next_first_ = (s + 1) * len_;
    return w;
  }
  // Calls add(entry) for every entry, target slabs side by side (the bodies beyond the
  // grains are one more target).
  template <typename Add>
  void apply(int threads, Add&& add) {
    std::vector<Entry>* b = buckets_.data();
    const std::size_t width = slabs_ + 1, sources = slabs_;
    const auto targets = static_cast<std::ptrdiff_t>(width);
#pragma omp parallel for num_threads(threads) \
    schedule(dynamic, 1) if (threads > 1 && n_ >= kParallelMin && sources >= 2)
    for (std::ptrdiff_t t = 0; t < targets; ++t)
      for (std::size_t s = 0; s < sources; ++s)
        for (const Entry& e : b[s * width + static_cast<std::size_t>(t)]) add(e);
  }
  // Gives the memory back (before a neighbour-list build, whose peak it would add to).
  void release() {
    std::vector<std::vector<Entry>>().swap(buckets_);
  }

 private:
  std::vector<std::vector<Entry>> buckets_;  // source-major: [s * (slabs + 1) + target]
  std::size_t n_ = 0, len_ = kMinSlab, slabs_ = 0;
};

// Threads of a run when none is asked for: GEODEM_THREADS, else OMP_NUM_THREADS, else 1
// (a run then never competes with the runs of a study or of a test suite for cores).
int default_threads();

// Whether the engine was built with OpenMP (else every loop runs on one thread).
bool built_with_openmp();

}  // namespace geodem
