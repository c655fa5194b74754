// A decomposed domain (domain/slab_domain.hpp) ends in the bits of one process. The ranks here
// are threads that pass their messages through shared memory (ThreadComm), so that the
// migration, ghost and history code runs in the ordinary and the sanitizer builds; the MPI
// transport runs the same comparison across processes (tests/mpi/test_domain.py).
#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <cmath>
#include <map>
#include <thread>

#include "domain_ranks.hpp"
#include "pressed_packing.hpp"
#include "world/world_editing.hpp"

namespace geodem::test {
namespace {

// `one_slab`: the force stage in one slab (one process's reference, and ranks that keep its
// bits); else a decomposed world's slabs follow blocks of keys, and `threads` share them.
template <int D>
World<D> packing(bool extras, int sort_interval, bool one_slab = true, int threads = 1) {
  World<D> w = pressed_packing<D>(extras, D == 2 ? 6000 : 4000, D == 2 ? 80 : 16, 40.0, 5);
  w.sort_interval = sort_interval;
  w.one_slab = one_slab;
  w.threads = threads;
  return w;
}

constexpr int kSteps = 300;

template <int D>
void advance(World<D>& w, int from = 0, int to = kSteps) {
  for (int k = from; k < to; ++k) {
    if (k == 100) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);  // the floor slides
    w.measure_this_step = k + 1 == kSteps;                       // the statistics of the last step
    step(w);
  }
}

// The packing advanced on `ranks` ranks (threads); also says whether grains changed ranks,
// and gives each rank's sums (taken on the ranks: they are collective).
template <int D>
std::vector<World<D>> on_ranks(bool extras, int sort_interval, int ranks, bool& moved,
                               std::vector<Sums<D>>& sums, int rebalance_every = 10,
                               bool* cuts_moved = nullptr, bool one_slab = true,
                               int threads_each = 1) {
  Hub hub(ranks);
  std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
  std::vector<std::uint64_t> migrated(parts.size(), 0);
  sums.assign(parts.size(), Sums<D>{});
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      auto& w = parts[static_cast<std::size_t>(r)];
      w = packing<D>(extras, sort_interval, one_slab, threads_each);
      auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
      d->rebalance_every = rebalance_every;
      // Moved by measured times whenever they differ, at once and all the way (big moves:
      // grains change ranks; the damped moves are tested in balanced_cuts_test.cpp).
      d->rebalance_tolerance = 0.0;
      d->rebalance_persistence = 1;
      d->rebalance_damping = 1.0;
      d->rebalance_on_time = true;
      const std::vector<double> cuts = d->cuts();
      advance(w);
      if (cuts_moved && r == 0) *cuts_moved = d->cuts() != cuts;
      migrated[static_cast<std::size_t>(r)] = d->migrated();
      sums[static_cast<std::size_t>(r)] = sums_of(w);
    });
  for (auto& t : threads) t.join();
  moved = false;
  for (std::uint64_t m : migrated) moved |= m > 0;
  return parts;
}

template <typename T>
class DomainTest : public ::testing::Test {};
TYPED_TEST_SUITE(DomainTest, Dims, DimNames);

// Grains kept in id order (sort_interval = 0): three ranks end in the bits of one process
// with its grains in id order and one force slab; the walls' forces and the contact
// statistics, summed exactly over ranks, are the same on every rank and within 1e-12 of
// the one process's sums.
TYPED_TEST(DomainTest, ThreeRanksGiveTheBitsOfOneProcess) {
  constexpr int D = TypeParam::value;
  for (bool extras : {false, true}) {
    SCOPED_TRACE(extras ? "rolling springs and bonds" : "frictional");
    World<D> one = packing<D>(extras, 0);
    advance(one);
    bool moved = false;
    std::vector<Sums<D>> sums;
    const auto parts = on_ranks<D>(extras, 0, 3, moved, sums);
    std::size_t ghosts = 0;
    std::vector<Grain<D>> reference(one.particles.size());
    for (std::size_t i = 0; i < one.particles.size(); ++i)
      reference[one.particles.id[i]] = {one.particles.pos[i], one.particles.vel[i],
                                        one.particles.angvel[i], true};
    expect_same<D>(by_id(parts, one.particles.size(), ghosts), reference);
    for (const auto& w : parts) EXPECT_EQ(w.dt, one.dt);
    // Every rank holds the domain's sums; one process sums in its own order (1e-12).
    EXPECT_GT(one.stats.wall_contacts, 0u);
    for (const auto& s : sums) expect_sums<D>(s, sums[0], 0.0);
    expect_sums<D>(sums_of(one), sums[0], 1e-12);
    EXPECT_GT(ghosts, 0u);
    EXPECT_TRUE(moved) << "no grain changed rank: the case does not test migration";
    EXPECT_GE(one.nlist.builds, 4u);
  }
}

// Grains put in cell order every 3 list builds (keys retaken by their owners), and the cuts
// moved at every build to balance the ranks' measured times: 1, 2 and 3 ranks end in the same
// bits, grains and the domain's sums, and the ranks' grains did leave id order. The force
// stage runs in slabs of blocks of keys (several on one rank), the ranks of 2 and 3 on two
// threads each, the rank of 1 on one: a grain sums its contacts in the same order however
// many grains its rank holds and however many threads share them.
TYPED_TEST(DomainTest, RanksInCellOrderAgree) {
  constexpr int D = TypeParam::value;
  bool cuts_moved = false;  // in some of the runs (they follow measured times)
  for (bool extras : {false, true}) {
    SCOPED_TRACE(extras ? "rolling springs and bonds" : "frictional");
    bool moved = false;
    std::size_t ghosts = 0;
    std::vector<Sums<D>> one_sums, sums;
    const auto one = on_ranks<D>(extras, 3, 1, moved, one_sums, 10, nullptr, false, 1);
    const std::size_t n = one[0].particles.size();
    EXPECT_FALSE(std::is_sorted(one[0].particles.id.begin(), one[0].particles.id.end()));
    EXPECT_GE(one[0].slab_starts.size(), 3u) << "one slab: no crossing between slabs is tested";
    const auto reference = by_id(one, n, ghosts);
    for (int ranks : {2, 3}) {
      SCOPED_TRACE(::testing::Message() << ranks << " ranks");
      bool moved_here = false;
      const auto parts = on_ranks<D>(extras, 3, ranks, moved, sums, 1, &moved_here, false, 2);
      cuts_moved |= moved_here;
      expect_same<D>(by_id(parts, n, ghosts), reference);
      EXPECT_GT(ghosts, 0u);
      EXPECT_TRUE(moved);
      for (const auto& w : parts) EXPECT_EQ(w.dt, one[0].dt);
      for (const auto& s : sums) expect_sums<D>(s, one_sums[0], 0.0);  // exact: the same bits
    }
  }
  EXPECT_TRUE(cuts_moved);
}

// Slabs of blocks of ids (keys retaken never), one rank on two threads and three ranks on
// one: the same bits.
TYPED_TEST(DomainTest, ThreadsInsideRanksKeepTheBits) {
  constexpr int D = TypeParam::value;
  bool moved = false;
  std::size_t ghosts = 0;
  std::vector<Sums<D>> one_sums, sums;
  const auto one = on_ranks<D>(true, 0, 1, moved, one_sums, 0, nullptr, false, 2);
  const std::size_t n = one[0].particles.size();
  EXPECT_GE(one[0].slab_starts.size(), 3u);
  const auto reference = by_id(one, n, ghosts);
  const auto parts = on_ranks<D>(true, 0, 3, moved, sums, 0, nullptr, false, 1);
  expect_same<D>(by_id(parts, n, ghosts), reference);
  EXPECT_TRUE(moved);
  for (const auto& w : parts) EXPECT_EQ(w.dt, one[0].dt);
  for (const auto& s : sums) expect_sums<D>(s, one_sums[0], 0.0);
}

// Grains removed in a band halfway (a stage's excavation): every rank removes its grains and
// ghosts there, and 1 and 3 ranks still end in the same bits, with the same grains left.
TYPED_TEST(DomainTest, RemovingGrainsKeepsTheBitsOfOneRank) {
  constexpr int D = TypeParam::value;
  // A band across the middle of the column: the grains above it fall into the gap.
  const double lo = (D == 2 ? 30 : 6) * 1.96 * kPackedRadius, hi = lo + 6 * 1.96 * kPackedRadius;
  auto run = [&](int ranks) {
    Hub hub(ranks);
    std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
    std::vector<std::size_t> removed(parts.size(), 0);
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
      threads.emplace_back([&, r] {
        auto& w = parts[static_cast<std::size_t>(r)];
        w = packing<D>(true, 3);
        SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
        advance(w, 0, 150);
        const auto& P = w.particles;
        removed[static_cast<std::size_t>(r)] = remove_grains(
            w,
            grains_where(w, [&](std::size_t i) { return P.pos[i].y() > lo && P.pos[i].y() < hi; }),
            ContactHistory::kKeep);
        advance(w, 150, kSteps);
      });
    for (auto& t : threads) t.join();
    EXPECT_GT(removed[0], 0u);
    std::map<std::uint32_t, Grain<D>> left;
    for (const auto& w : parts)
      for (std::size_t i = 0; i < w.particles.size(); ++i)
        if (!(w.particles.flags[i] & kGhost))
          left[w.particles.id[i]] = {w.particles.pos[i], w.particles.vel[i], w.particles.angvel[i],
                                     true};
    return left;
  };
  const auto one = run(1), three = run(3);
  ASSERT_EQ(one.size(), three.size());
  EXPECT_LT(one.size(), static_cast<std::size_t>(D == 2 ? 6000 : 4000));
  for (const auto& [id, g] : one) {
    const auto it = three.find(id);
    ASSERT_TRUE(it != three.end()) << "grain " << id;
    ASSERT_TRUE(g.pos == it->second.pos && g.vel == it->second.vel && g.angvel == it->second.angvel)
        << "grain " << id;
  }
}

// The top of the left half removed at the start (the first rank's slab then has half the
// second's grains): with the cuts moved by the modelled work (a grain and its contacts) every 2
// builds, the ranks own about as many grains again; with the cuts kept they stay apart. The
// bits are those of one rank either way.
TYPED_TEST(DomainTest, ModelledWorkEvensTheRanks) {
  constexpr int D = TypeParam::value;
  auto run = [&](int ranks, int every, std::vector<std::size_t>& owned) {
    Hub hub(ranks);
    std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
    owned.assign(parts.size(), 0);
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
      threads.emplace_back([&, r] {
        auto& w = parts[static_cast<std::size_t>(r)];
        w = packing<D>(false, 3);
        typename Dim<D>::Vec mid = Dim<D>::Vec::Zero();
        for (const auto& x : w.particles.pos) mid += x;
        mid /= static_cast<double>(w.particles.size());
        auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
        d->rebalance_every = every;
        const auto& P = w.particles;
        remove_grains(
            w,
            grains_where(
                w, [&](std::size_t i) { return P.pos[i].x() < mid.x() && P.pos[i].y() > mid.y(); }),
            ContactHistory::kKeep);
        advance(w);
        owned[static_cast<std::size_t>(r)] = d->owned(w);
      });
    for (auto& t : threads) t.join();
    return parts;
  };
  std::vector<std::size_t> one_owned, kept, evened;
  std::size_t ghosts = 0;
  const auto one = run(1, 2, one_owned);
  const std::size_t ids = one[0].particles.next_id;
  const auto reference = by_id(one, ids, ghosts);
  const auto fixed = run(2, 0, kept);
  const auto moved = run(2, 2, evened);
  expect_same<D>(by_id(fixed, ids, ghosts), reference);
  expect_same<D>(by_id(moved, ids, ghosts), reference);
  const auto ratio = [](const std::vector<std::size_t>& n) {
    return static_cast<double>(std::max(n[0], n[1])) / static_cast<double>(std::min(n[0], n[1]));
  };
  EXPECT_GT(ratio(kept), 1.3) << kept[0] << " and " << kept[1] << " grains: the case is even";
  EXPECT_LT(ratio(evened), 1.1) << evened[0] << " and " << evened[1] << " grains";
}

// A checkpoint of a decomposed run (the whole domain gathered on rank 0 as one world, the
// contact history as records with the keys) resumed on another number of ranks goes on with
// the bits of the uninterrupted run: 3 ranks stopped at step 150, resumed on 2 and on 1
// (force slabs of blocks of keys, which the checkpoint keeps).
TYPED_TEST(DomainTest, ACheckpointResumesOnOtherRankCounts) {
  constexpr int D = TypeParam::value;
  constexpr int kCut = 150;
  bool moved = false;
  std::size_t ghosts = 0;
  std::vector<Sums<D>> sums;
  const auto uninterrupted = on_ranks<D>(true, 3, 3, moved, sums, 0, nullptr, false, 1);
  std::size_t n = 0;
  for (const auto& w : uninterrupted) n += w.particles.size();
  n -= ghosts_in(uninterrupted);
  const auto reference = by_id(uninterrupted, n, ghosts);
  const SavedDomain saved = checkpoint_on_ranks<D>(
      3, [] { return packing<D>(true, 3, false); }, [](World<D>& w) { advance(w, 0, kCut); });
  EXPECT_EQ(saved.grains, n);
  EXPECT_GT(saved.pairs, 0u);
  for (int ranks : {2, 1}) {
    SCOPED_TRACE(::testing::Message() << "resumed on " << ranks << " ranks");
    const auto parts = resume_on_ranks<D>(
        ranks, saved, [] { return packing<D>(true, 3, true, 2); },
        [](World<D>& w) { advance(w, kCut, kSteps); });
    expect_same<D>(by_id(parts, n, ghosts), reference);
    for (const auto& w : parts) EXPECT_EQ(w.dt, uninterrupted[0].dt);
  }
}

}  // namespace
}  // namespace geodem::test
