// Fixed shares of work items per thread, with the leftovers taken over (base/slab_shares.hpp):
// every item runs exactly once, whatever the thread count, the item count, and however slow
// some items are (slow items make the other threads take over the rest of a share).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <thread>
#include <vector>

#include "base/slab_shares.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace geodem::test {
namespace {

// Runs n items on `threads` threads; returns how often each item ran. Items in `slow` sleep, so
// that the other threads finish their shares first and take over the slow thread's leftovers.
std::vector<int> runs_of_each(std::size_t n, int threads, std::size_t slow_from = ~std::size_t{0}) {
  auto count = std::make_unique<std::atomic<int>[]>(n);
  run_in_shares(n, threads, [&](std::size_t k) {
    if (k >= slow_from) std::this_thread::sleep_for(std::chrono::microseconds(200));
    count[k].fetch_add(1, std::memory_order_relaxed);
  });
  std::vector<int> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = count[k].load();
  return out;
}

TEST(SlabShares, EveryItemRunsExactlyOnce) {
  for (int threads : {1, 2, 3, 4, 7, 8, kMaxShares, kMaxShares + 3})
    for (std::size_t n : {0u, 1u, 2u, 3u, 5u, 17u, 64u, 100u, 1001u}) {
      const auto runs = runs_of_each(n, threads);
      for (std::size_t k = 0; k < n; ++k)
        ASSERT_EQ(runs[k], 1) << "item " << k << " of " << n << " on " << threads << " threads";
    }
}

TEST(SlabShares, SlowShareIsTakenOverAndStillRunsOnce) {
  // The last share's items are slow: its owner falls behind and the others take its back end.
  for (int threads : {2, 3, 4})
    for (std::size_t n : {8u, 33u}) {
      const auto runs = runs_of_each(n, threads, n - n / static_cast<std::size_t>(threads));
      for (std::size_t k = 0; k < n; ++k)
        ASSERT_EQ(runs[k], 1) << "item " << k << " of " << n << " on " << threads << " threads";
    }
}

#ifdef _OPENMP
TEST(SlabShares, OwnersRunTheirSharesFrontToBack) {
  // With no item slower than another, thread t starts on the front of share t: the first item
  // of every share is run by its owner (the others take over from the backs only).
  const int threads = 2;
  const std::size_t n = 40;
  std::vector<int> by(n, -1);
  std::atomic<int> team{0};
  run_in_shares(n, threads, [&](std::size_t k) {
    by[k] = omp_get_thread_num();
    team.store(omp_get_num_threads());
    // Long enough (20 ms a share) that no thread runs out of its own share and the other's
    // before that one has started.
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  if (team.load() == threads) {
    EXPECT_EQ(by[0], 0);
    EXPECT_EQ(by[n / 2], 1);
  }
  for (std::size_t k = 0; k < n; ++k) EXPECT_GE(by[k], 0);
}
#endif

}  // namespace
}  // namespace geodem::test
