// Two phases over slabs in one parallel region (base/slab_phases.hpp): every phase runs once,
// and phase two of a slab starts only after phase one of the slab itself and of every earlier
// slab that reaches it, whatever the thread count, the reaches and which items are slow. Also
// the index maximum that gives the force stage its reaches (base/index_max.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "base/index_max.hpp"
#include "base/slab_phases.hpp"

namespace geodem::test {
namespace {

struct Outcome {
  std::vector<int> ones, twos;  // how often each slab's phases ran
  int early = 0;                // phase twos that found a source they wait for not done
};

// `slow`: phase one of every slab from it on sleeps, so that the other threads run ahead.
Outcome run_phases(const std::vector<std::size_t>& reach, int threads, std::size_t slow) {
  const std::size_t n = reach.size();
  auto one_done = std::make_unique<std::atomic<int>[]>(n);
  auto ones = std::make_unique<std::atomic<int>[]>(n);
  auto twos = std::make_unique<std::atomic<int>[]>(n);
  std::atomic<int> early{0};
  SlabProgress progress;
  for (int pass = 0; pass < 3; ++pass) {  // (later passes reuse the marks of earlier ones)
    for (std::size_t s = 0; s < n; ++s) one_done[s].store(0);
    run_slab_phases(
        n, threads, true, progress,
        [&](std::size_t s) {
          progress.announce(s, reach[s]);
          if (s >= slow) std::this_thread::sleep_for(std::chrono::microseconds(300));
          ones[s].fetch_add(1);
          one_done[s].store(1);
        },
        [&](std::size_t s) {
          for (std::size_t a = 0; a <= s; ++a)
            if ((a == s || reach[a] >= s) && one_done[a].load() == 0) early.fetch_add(1);
          for (std::size_t a = 0; a < s; ++a)
            if (progress.reach(a) != reach[a]) early.fetch_add(1);
          twos[s].fetch_add(1);
        });
  }
  Outcome out;
  for (std::size_t s = 0; s < n; ++s) out.ones.push_back(ones[s].load());
  for (std::size_t s = 0; s < n; ++s) out.twos.push_back(twos[s].load());
  out.early = early.load();
  return out;
}

TEST(SlabPhases, EachPhaseOnceAndPhaseTwoAfterItsSources) {
  std::mt19937 rng(7);
  for (int threads : {1, 2, 3, 4, 7, kMaxShares + 3})
    for (std::size_t n : {0u, 1u, 2u, 3u, 5u, 10u, 17u, 40u}) {
      // Reaches from the slab itself to a few slabs on (as the force stage's), and one slab
      // reaching the last (a pair across the whole sample).
      std::vector<std::size_t> reach(n);
      for (std::size_t s = 0; s < n; ++s) reach[s] = std::min(n - 1, s + rng() % 3);
      if (n > 2) reach[1] = n - 1;
      for (std::size_t slow : {n, n / 2, std::size_t{0}}) {
        const Outcome o = run_phases(reach, threads, slow);
        for (std::size_t s = 0; s < n; ++s) {
          ASSERT_EQ(o.ones[s], 3) << "slab " << s << " of " << n << " on " << threads;
          ASSERT_EQ(o.twos[s], 3) << "slab " << s << " of " << n << " on " << threads;
        }
        ASSERT_EQ(o.early, 0) << n << " slabs on " << threads << " threads, slow from " << slow;
      }
    }
}

TEST(SlabPhases, SumsInSourceOrderAreTheSameOnAnyThreadCount) {
  // Phase one of slab a leaves a term for every slab it reaches; phase two adds them in source
  // order to a value that depends on that order (floating-point rounding): the serial result.
  const std::size_t n = 23;
  std::vector<std::size_t> reach(n);
  for (std::size_t s = 0; s < n; ++s) reach[s] = std::min(n - 1, s + 1 + s % 3);
  auto sums = [&](int threads) {
    std::vector<double> term(n * n, 0.0), total(n, 0.0);
    SlabProgress progress;
    run_slab_phases(
        n, threads, true, progress,
        [&](std::size_t a) {
          progress.announce(a, reach[a]);
          if (a % 4 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
          for (std::size_t t = a + 1; t <= reach[a]; ++t)
            term[a * n + t] = 1.0 / static_cast<double>(3 + a + 7 * t);
        },
        [&](std::size_t s) {
          double x = 1e16 * static_cast<double>(s % 2);
          for (std::size_t a = 0; a < s; ++a)
            if (progress.reach(a) >= s) x += term[a * n + s];
          total[s] = x;
        });
    return total;
  };
  const auto one = sums(1);
  for (int threads : {2, 3, 5}) {
    const auto many = sums(threads);
    for (std::size_t s = 0; s < n; ++s) ASSERT_EQ(one[s], many[s]) << "slab " << s;
  }
  EXPECT_GT(one[n - 1], 0.0);
}

TEST(IndexMax, LargestIndexOrTheFloor) {
  std::mt19937 rng(3);
  for (std::size_t n : {0u, 1u, 7u, 15u, 16u, 17u, 63u, 100u, 1000u, 4099u}) {
    std::vector<std::uint32_t> v(n);
    for (auto& x : v) x = static_cast<std::uint32_t>(rng());
    const std::uint32_t top = n ? *std::max_element(v.begin(), v.end()) : 0u;
    EXPECT_EQ(max_index(v.data(), n, 0u), top) << n;
    EXPECT_EQ(max_index(v.data(), n, 0xffffffffu), 0xffffffffu) << n;
    // Above 2^31 (an unsigned comparison throughout).
    if (n > 0) {
      v[n / 2] = 0x80000001u;
      const std::uint32_t now = *std::max_element(v.begin(), v.end());
      EXPECT_GE(now, 0x80000001u);
      EXPECT_EQ(max_index(v.data(), n, 5u), now) << n;
    }
  }
}

}  // namespace
}  // namespace geodem::test
