// Two passes over the slabs in one parallel region: phase one of every slab, then phase two of
// every slab, where phase two of slab s reads what phase one of slabs a <= s wrote for it
// (the force stage: the pairs of slab a add forces to grains of slabs from a up to a's
// reach; phase two adds them up and then the walls, contacts/contact_forces.cpp).
//
// Why one region: with a barrier between the passes every thread waits for the slowest one
// at the end of phase one, a step's largest idle time where the slabs' work differs (ten
// slabs on two threads, the last one shorter: about a twentieth of the phase on one thread).
// Here phase two of slab s starts as soon as phase one is done on the slabs that reach s,
// which each slab's phase one announces before its work (its `reach`: the highest slab it
// writes to). Each thread owns a share of the slabs as in base/slab_shares.hpp (run_slab_phases
// says in which order it runs them and takes over the others').
//
// Never a deadlock: only a phase two waits, and only for phase ones of slabs up to its own; no
// thread takes a share's phase two before every phase one of that share is taken, and a phase
// one never waits.
// Which thread runs what never changes a result: the phases write their slab's own data, and
// phase two reads a source slab's data only once that slab's phase one is done.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>

#include "base/slab_shares.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace geodem {

// Where each slab's phase one stands in the current pass. Kept between passes (a step
// allocates nothing): a pass's stamp tells its marks from those of the passes before.
class SlabProgress {
 public:
  // Starts a pass over `slabs` slabs.
  void begin_pass(std::size_t slabs) {
    if (slabs > capacity_ || ++stamp_ == 0) {
      capacity_ = std::max(slabs, capacity_);
      reach_ = std::make_unique<std::atomic<std::uint64_t>[]>(capacity_);
      done_ = std::make_unique<std::atomic<std::uint32_t>[]>(capacity_);
      stamp_ = 1;
    }
  }
  // Phase one of slab a writes for slabs up to `reach` (>= a): announced before its work.
  void announce(std::size_t a, std::size_t reach) {
    reach_[a].store((std::uint64_t{stamp_} << 32) | reach, std::memory_order_release);
  }
  void mark_done(std::size_t a) { done_[a].store(stamp_, std::memory_order_release); }
  // Slab a's reach, once announced in this pass (after wait_for_sources of a later slab).
  std::size_t reach(std::size_t a) const {
    return static_cast<std::uint32_t>(reach_[a].load(std::memory_order_relaxed));
  }
  // Whether phase one of slab s and of every earlier slab that reaches s is done.
  bool sources_done(std::size_t s) const {
    if (done_[s].load(std::memory_order_acquire) != stamp_) return false;
    for (std::size_t a = 0; a < s; ++a) {
      const std::uint64_t r = reach_[a].load(std::memory_order_acquire);
      if ((r >> 32) != stamp_) return false;
      if (static_cast<std::uint32_t>(r) >= s && done_[a].load(std::memory_order_acquire) != stamp_)
        return false;
    }
    return true;
  }
  // Waits until sources_done(s).
  void wait_for_sources(std::size_t s) const {
    for (std::size_t a = 0; a < s; ++a) {
      std::uint64_t r = 0;
      spin_until([&] {
        r = reach_[a].load(std::memory_order_acquire);
        return (r >> 32) == stamp_;
      });
      if (static_cast<std::uint32_t>(r) >= s)
        spin_until([&] { return done_[a].load(std::memory_order_acquire) == stamp_; });
    }
    spin_until([&] { return done_[s].load(std::memory_order_acquire) == stamp_; });
  }

 private:
  template <typename Ready>
  static void spin_until(Ready&& ready) {
    for (unsigned spins = 0; !ready(); ++spins) pause(spins);
  }

 public:
  // One round of waiting for another thread's work.
  static void pause(unsigned spins) {
#if defined(__x86_64__)
    _mm_pause();
#endif
    // The slab waited for may be on a thread the system has paused: let it run.
    if (spins >= 4096) std::this_thread::yield();
  }

 private:
  std::unique_ptr<std::atomic<std::uint64_t>[]> reach_;
  std::unique_ptr<std::atomic<std::uint32_t>[]> done_;
  std::size_t capacity_ = 0;
  std::uint32_t stamp_ = 0;
};

// Runs, for every slab s in [0, slabs): first(s), which returns after calling
// progress.announce(s, reach) first and before its slab's work, then second(s) once first(a)
// is done for a = s and every a < s whose reach is s or beyond. `parallel`: on up to
// `threads` threads; else slab by slab, first(s) then second(s), on the calling thread.
template <typename First, typename Second>
void run_slab_phases(std::size_t slabs, int threads, bool parallel, SlabProgress& progress,
                     First&& first, Second&& second) {
  progress.begin_pass(slabs);
  auto one = [&](std::size_t s) {
    first(s);
    progress.mark_done(s);
  };
  auto two = [&](std::size_t s) {
    progress.wait_for_sources(s);
    second(s);
  };
  if (!parallel || threads <= 1 || slabs < 2) {
    for (std::size_t s = 0; s < slabs; ++s) one(s), two(s);
    return;
  }
  if (threads > kMaxShares) {  // every phase one before any phase two, claimed in that order
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::ptrdiff_t k = 0; k < 2 * static_cast<std::ptrdiff_t>(slabs); ++k) {
      const auto u = static_cast<std::size_t>(k);
      if (u < slabs)
        one(u);
      else
        two(u - slabs);
    }
    return;
  }
  // Share t: the slabs [t n / T, (t + 1) n / T), its phase ones and its phase twos each a range
  // of slabs claimed from both ends. A thread looks for work in its own share first, then in
  // the others': phase ones (its own from the front, the others' from the back), then a phase
  // two whose sources are done, from the last slab down or else from the first up. It waits
  // only when no phase one is left and no phase two is ready (their phase ones are running).
  using shares_detail::claim;
  shares_detail::Share ones[kMaxShares], twos[kMaxShares];
  const auto count = static_cast<std::size_t>(threads);
  for (std::size_t t = 0; t < count; ++t) {
    const auto pack = shares_detail::pack(slabs * t / count, slabs * (t + 1) / count);
    ones[t].range.store(pack, std::memory_order_relaxed);
    twos[t].range.store(pack, std::memory_order_relaxed);
  }
  // Claims a phase two of share `sh` whose sources are done; false when none is ready now.
  // `left`: set when the share still has phase twos (ready or not).
  auto ready_two = [&](shares_detail::Share& sh, bool& left, std::uint32_t& k) {
    std::uint64_t r = sh.range.load(std::memory_order_relaxed);
    for (;;) {
      const auto front = static_cast<std::uint32_t>(r);
      const auto end = static_cast<std::uint32_t>(r >> 32);
      if (front >= end) return false;
      left = true;
      std::uint64_t next;
      if (progress.sources_done(end - 1)) {
        next = shares_detail::pack(front, end - 1u), k = end - 1u;
      } else if (progress.sources_done(front)) {
        next = shares_detail::pack(front + 1u, end), k = front;
      } else {
        return false;
      }
      if (sh.range.compare_exchange_weak(r, next, std::memory_order_relaxed)) return true;
    }
  };
#pragma omp parallel num_threads(threads)
  {
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    std::uint32_t k = 0;
    for (unsigned idle = 0;;) {
      bool found = false, left = false;
      for (int d = 0; d < threads && !found; ++d) {
        const int s = (t + d) % threads;
        if (claim(ones[s], d != 0, k)) {
          one(k);
          found = true;
        } else if (ready_two(twos[s], left, k)) {
          two(k);
          found = true;
        }
      }
      if (found) {
        idle = 0;
      } else if (!left) {
        break;
      } else {
        SlabProgress::pause(idle++);
      }
    }
  }
}

}  // namespace geodem
