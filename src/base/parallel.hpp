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
#include <cstdint>
#include <vector>

#include "base/slab_shares.hpp"

namespace geodem {

// Loops shorter than this run on the calling thread: a parallel region costs a few
// microseconds, the work of a few thousand grains.
constexpr std::size_t kParallelMin = 4096;

// Runs body(i) for i in [0, n): on up to `threads` threads when `parallel` holds (a static
// schedule), otherwise on the calling thread without entering OpenMP. (A region that an `if`
// clause leaves to one thread still costs libgomp a system call, a futex wake at its closing
// barrier: about 0.5 us on a virtual machine, paid several times a step by a small model.)
template <typename Body>
void for_each_index(std::ptrdiff_t n, int threads, bool parallel, Body&& body) {
  if (parallel && threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
    return;
  }
  for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
}

// The largest (`Largest`) or smallest of `init` and term(i) over i in [0, n), the terms taken
// as for_each_index runs them: exact in any order.
template <bool Largest, typename Term>
double extreme_over_indices(std::ptrdiff_t n, int threads, bool parallel, double init,
                            Term&& term) {
  double m = init;
  auto take = [](double a, double b) { return Largest ? std::max(a, b) : std::min(a, b); };
  if (parallel && threads > 1) {
    if constexpr (Largest) {
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : m)
      for (std::ptrdiff_t i = 0; i < n; ++i) m = take(m, term(i));
    } else {
#pragma omp parallel for num_threads(threads) schedule(static) reduction(min : m)
      for (std::ptrdiff_t i = 0; i < n; ++i) m = take(m, term(i));
    }
    return m;
  }
  for (std::ptrdiff_t i = 0; i < n; ++i) m = take(m, term(i));
  return m;
}

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
  for_each_index(static_cast<std::ptrdiff_t>(blocks), threads, n >= kParallelMin,
                 [&](std::ptrdiff_t b) {
                   const std::size_t lo = static_cast<std::size_t>(b) * kSumBlock;
                   const std::size_t hi = lo + kSumBlock < n ? lo + kSumBlock : n;
                   T s = zero;
                   for (std::size_t i = lo; i < hi; ++i) s += term(i);
                   part[static_cast<std::size_t>(b)] = s;
                 });
  T total = zero;
  for (std::size_t b = 0; b < blocks; ++b) total += part[b];
  return total;
}

// Slabs: fixed ranges of grain indices that stages writing to both grains of a pair run
// side by side (contacts/contact_forces.cpp). Their length depends on the grain count
// alone, never on the thread count: long enough that few pairs cross slabs and that a
// slab's work (about 100 us for 1,024 grains) dwarfs the cost of handing it to a thread,
// short enough for 32 slabs to share among threads.
// A caller may fix the length instead (`fixed` > 0), or give the slabs' starts (SlabPlan).
constexpr std::size_t kMinSlab = 1024;
// Slabs (for_slabs, SlabCrossings::apply) go to threads from two slabs on: a slab's contacts
// are work enough for a region's cost, where the loops of for_each_index keep kParallelMin
// (lowered with them, a 2D pull-out's clump integration ran slower on two threads than on
// one: docs/performance.md).
constexpr std::size_t kParallelSlabsMin = 2 * kMinSlab;
inline std::size_t slab_length(std::size_t n, std::size_t fixed = 0) {
  return fixed > 0 ? fixed : std::max<std::size_t>(kMinSlab, (n + 31) / 32);
}

// How a stage cuts n grains into slabs: ranges of one length (the last one shorter), or
// ranges that begin at given indices. A decomposed domain gives starts where its grains'
// keys change block (domain/slab_domain.hpp): a grain's slab, and so the order of its sums,
// is then the same on every rank that holds it, whatever the rank's other grains.
struct SlabPlan {
  std::size_t n = 0;
  std::size_t len = kMinSlab;             // uniform slabs (starts == nullptr)
  const std::uint32_t* starts = nullptr;  // else starts[0] = 0 < ... < starts[count] = n
  std::size_t count = 0;

  static SlabPlan uniform(std::size_t n, std::size_t fixed = 0) {
    SlabPlan p;
    p.n = n;
    p.len = slab_length(n, fixed);
    p.count = (n + p.len - 1) / p.len;
    return p;
  }
  // `starts` holds count + 1 entries, the last n.
  static SlabPlan given(std::size_t n, const std::vector<std::uint32_t>& starts) {
    SlabPlan p;
    p.n = n;
    p.starts = starts.data();
    p.count = starts.size() - 1;
    return p;
  }
  std::size_t first(std::size_t s) const { return starts ? starts[s] : s * len; }
  std::size_t last(std::size_t s) const {
    return starts ? starts[s + 1] : std::min(n, (s + 1) * len);
  }
  // The slab of grain i < n.
  std::size_t slab_of(std::size_t i) const {
    if (!starts) return i / len;
    return static_cast<std::size_t>(std::upper_bound(starts + 1, starts + count + 1, i) -
                                    (starts + 1));
  }
};

// Whether for_slabs hands the slabs to threads (else no region: for_each_index).
inline bool slabs_on_threads(const SlabPlan& plan, int threads) {
  return threads > 1 && plan.count >= 2 && plan.n >= kParallelSlabsMin;
}

// Runs body(slab, first, last) for every slab of the plan, side by side.
template <typename Body>
void for_slabs(const SlabPlan& plan, int threads, Body&& body) {
  const auto ns = static_cast<std::ptrdiff_t>(plan.count);
  auto run = [&](std::ptrdiff_t s) {
    const auto slab = static_cast<std::size_t>(s);
    body(slab, plan.first(slab), plan.last(slab));
  };
  if (slabs_on_threads(plan, threads)) {
    run_in_shares(plan.count, threads, [&](std::size_t s) { run(static_cast<std::ptrdiff_t>(s)); });
    return;
  }
  for (std::ptrdiff_t s = 0; s < ns; ++s) run(s);
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
  static constexpr std::size_t kFirstBlock = (std::size_t{256} << 10) / sizeof(Entry) + 1;

 public:
  // Buckets for n grains; their contents are left to the slabs' tasks to clear.
  void prepare(const SlabPlan& plan, int threads) {
    // Writers on threads must not share the spare blocks (recycle): none are left to them.
    if (slabs_on_threads(plan, threads)) spare_.clear();
    plan_ = plan;
    slabs_ = plan.count;
    if (buckets_.size() < slabs_ * (slabs_ + 1)) buckets_.resize(slabs_ * (slabs_ + 1));
  }
  // Where the task of slab s writes: emptied here, filled by push().
  class Writer {
   public:
    // Inlined into the pair loops, which push one entry for a large share of their pairs on a
    // wide bed (a call each cost 7 % of a dense bed's step); the growth stays out of line.
    [[gnu::always_inline]] void push(const Entry& e) {
      // Most crossing pairs reach the next slab: spared the division.
      const std::size_t b = e.body;
      const std::size_t target = b >= plan_->n                 ? slabs_
                                 : b - next_first_ < next_len_ ? next_
                                                               : plan_->slab_of(b);
      std::vector<Entry>& bucket = bucket_[target];
      if (bucket.size() == bucket.capacity()) [[unlikely]]
        grow(bucket);
      bucket.push_back(e);
    }

   private:
    [[gnu::noinline]] void grow(std::vector<Entry>& bucket) {
      // An empty bucket takes the block of one that recycle() emptied, if any (slabs run one
      // after the other only: on threads nothing is recycled, so nothing shared is written
      // here). A fresh block is large enough for the allocator to map it apart from the heap
      // (the command line sets a 256 kB threshold), so that release() gives its pages back;
      // pages that no entry reached are never touched, so never resident.
      if (bucket.capacity() == 0 && !spare_->empty()) {
        bucket.swap(spare_->back());
        spare_->pop_back();
      } else {
        bucket.reserve(std::max(kFirstBlock, 2 * bucket.capacity()));
      }
    }
    friend class SlabCrossings;
    std::vector<Entry>* bucket_;
    std::vector<std::vector<Entry>>* spare_;
    const SlabPlan* plan_;
    std::size_t slabs_;
    std::size_t next_, next_first_, next_len_;  // the slab after the writer's, its first body
  };
  Writer slab(std::size_t s) {
    Writer w;
    w.bucket_ = buckets_.data() + s * (slabs_ + 1);
    w.spare_ = &spare_;
    for (std::size_t t = 0; t <= slabs_; ++t) w.bucket_[t].clear();
    w.plan_ = &plan_, w.slabs_ = slabs_;
    // For the last slab there is no next one: bodies from n up go to slabs_.
    w.next_ = s + 1;
    w.next_first_ = s + 1 < slabs_ ? plan_.first(s + 1) : plan_.n;
    w.next_len_ = s + 1 < slabs_ ? plan_.last(s + 1) - w.next_first_ : 0;
    return w;
  }
  // Calls add(entry) for every entry, target slabs side by side (the bodies beyond the
  // grains are one more target).
  template <typename Add>
  void apply(int threads, Add&& add) {
    const std::size_t targets = slabs_ + 1;
    if (threads > 1 && plan_.n >= kParallelSlabsMin && slabs_ >= 2) {  // (else no region)
      // Target slab t falls in the same share as the force stage's slab t.
      run_in_shares(targets, threads, [&](std::size_t t) { apply_to(t, add); });
      return;
    }
    for (std::size_t t = 0; t < targets; ++t) apply_to(t, add);
  }
  // Calls add(entry) for the entries of one target (slab `target`, or slab count for the
  // bodies beyond the grains), in (source slab, entry) order: for a stage that goes on with
  // the target's bodies in the same task.
  template <typename Add>
  void apply_to(std::size_t target, Add&& add) const {
    const std::size_t width = slabs_ + 1;
    for (std::size_t s = 0; s < slabs_; ++s)
      for (const Entry& e : buckets_[s * width + target]) add(e);
  }
  // Once target slab t's entries are added (slabs run one after the other), its buckets'
  // blocks go to the buckets that the later slabs fill: the crossings of about one slab are
  // resident at a time, not those of the whole step.
  void recycle(std::size_t target) {
    const std::size_t width = slabs_ + 1;
    for (std::size_t s = 0; s < slabs_ && s < target; ++s) {
      std::vector<Entry>& b = buckets_[s * width + target];
      if (b.capacity() == 0) continue;
      b.clear();
      spare_.emplace_back();
      spare_.back().swap(b);
    }
  }
  // Gives the memory back (before a neighbour-list build, whose peak it would add to).
  void release() {
    std::vector<std::vector<Entry>>().swap(buckets_);
    std::vector<std::vector<Entry>>().swap(spare_);
  }

 private:
  std::vector<std::vector<Entry>> buckets_;  // source-major: [s * (slabs + 1) + target]
  std::vector<std::vector<Entry>> spare_;    // emptied blocks (recycle)
  SlabPlan plan_;                            // its starts, if any, must outlive the writers
  std::size_t slabs_ = 0;
};

// Threads of a run when none is asked for: GEODEM_THREADS, else OMP_NUM_THREADS, else 1
// (a run then never competes with the runs of a study or of a test suite for cores).
int default_threads();

// Whether the engine was built with OpenMP (else every loop runs on one thread).
bool built_with_openmp();

}  // namespace geodem
