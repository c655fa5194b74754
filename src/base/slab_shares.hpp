// Work items (slabs) handed to threads in fixed shares: each thread first runs its own share,
// front to back, then takes items from the back of the shares that are not done yet.
//
// Why fixed shares: the same thread then handles the same grains step after step, so their
// forces, list rows and springs stay in its core's caches. Handing each slab to whichever
// thread was free moved them between cores at every step; on a 2-vCPU virtual machine whose
// vCPUs share no cache this made a two-thread step 1.3 times slower than fixed shares
// (docs/performance.md, "Fixed shares of slabs per thread"). Why the stealing: a thread that
// falls behind (its slabs hold more contacts, or the host paused its vCPU) is helped, which
// plain static shares (OpenMP's schedule(static)) cannot do.
//
// Which thread runs an item never changes a result: every stage that runs items this way
// writes each item's own data, and sums over items are taken in item order afterwards.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace geodem {

namespace shares_detail {

// A share's items not yet claimed: [front, end), packed in one word so that its owner (at the
// front) and the helpers (at the back) claim with one compare-and-swap each.
struct alignas(64) Share {
  std::atomic<std::uint64_t> range{0};
};

inline std::uint64_t pack(std::uint64_t front, std::uint64_t end) {
  return (end << 32) | front;
}

// Claims the first item of the share (from_back: its last); false when none is left. The
// items write disjoint data and the parallel region's end orders them: relaxed is enough.
inline bool claim(Share& s, bool from_back, std::uint32_t& item) {
  std::uint64_t r = s.range.load(std::memory_order_relaxed);
  for (;;) {
    const auto front = static_cast<std::uint32_t>(r);
    const auto end = static_cast<std::uint32_t>(r >> 32);
    if (front >= end) return false;
    const std::uint64_t next = from_back ? pack(front, end - 1u) : pack(front + 1u, end);
    if (s.range.compare_exchange_weak(r, next, std::memory_order_relaxed)) {
      item = from_back ? end - 1u : front;
      return true;
    }
  }
}

}  // namespace shares_detail

// Shares kept on the stack; more threads than this fall back to a dynamic schedule.
constexpr int kMaxShares = 64;

// Runs run(k) once for every k in [0, n) (n < 2^32) on up to `threads` threads. Share t is
// the t-th of `threads` contiguous ranges of about n / threads items; thread t of a team of T
// runs shares t, t + T, ... (all of them when OpenMP gives one thread), then helps the others.
template <typename Run>
void run_in_shares(std::size_t n, int threads, Run&& run) {
  using shares_detail::claim;
  if (threads <= 1 || n < 2) {
    for (std::size_t k = 0; k < n; ++k) run(k);
    return;
  }
  if (threads > kMaxShares) {
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(n); ++k)
      run(static_cast<std::size_t>(k));
    return;
  }
  shares_detail::Share share[kMaxShares];
  const auto count = static_cast<std::size_t>(threads);
  for (std::size_t t = 0; t < count; ++t)
    share[t].range.store(shares_detail::pack(n * t / count, n * (t + 1) / count),
                         std::memory_order_relaxed);
#pragma omp parallel num_threads(threads)
  {
    int t = 0, team = 1;
#ifdef _OPENMP
    t = omp_get_thread_num();
    team = omp_get_num_threads();
#endif
    std::uint32_t k = 0;
    for (int s = t; s < threads; s += team)
      while (claim(share[s], false, k)) run(k);
    for (int d = 1; d < threads; ++d) {
      const int s = (t + d) % threads;
      while (claim(share[s], true, k)) run(k);
    }
  }
}

}  // namespace geodem
