// Spar chains in a decomposed domain (docs/parallel.md, "Spar chains"): every rank holds the
// whole chains and computes its own grains' contacts with them; the loads on the nodes and
// elements, the contact statistics and the nodes' share of the time step are summed exactly
// over the ranks, and the grain-spar springs travel with their grains. A sheet (2D, with
// bending stiffness) or a cable (3D) lying across a pressed packing, its last node pulled:
// 1, 2 and 3 ranks end in the same bits for every grain and every node, and a checkpoint of 3
// ranks resumes on 2 and 1 with the uninterrupted bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "domain_ranks.hpp"
#include "pressed_packing.hpp"

namespace geodem::test {
namespace {

constexpr int kSteps = 1500, kPull = 200;

// The pressed packing of the other domain tests (3,000 discs or 2,000 spheres) with a chain
// across it low in the column, its last node held; the floor slides from step 100 and the
// last node is pulled along x from step kPull.
template <int D>
World<D> packing_with_chain() {
  World<D> w = pressed_packing<D>(true, D == 2 ? 3000 : 2000, D == 2 ? 80 : 16, 40.0, 5);
  const double side = (D == 2 ? 80 : 16) * 1.96 * kPackedRadius;
  // Between two rows of the lattice (2D), or between rows and layers (3D).
  const double y = (D == 2 ? 12.0 : 4.0) * 1.96 * kPackedRadius;
  const auto sheet = add_material(w, linear_material(w.materials[0].kn, 0.5 * w.materials[0].kn,
                                                     0.5, 0.3, kPackedDensity, "sheet"));
  w.resolve_pair_laws();
  std::vector<Vec<D>> points;
  const int n = 40;
  for (int k = 0; k <= n; ++k)
    points.push_back(vec<D>(side * (0.05 + 0.9 * k / n), y, 7.5 * 1.96 * kPackedRadius));
  w.spars.add_chain("sheet", points, 2.0 * w.materials[0].kn * kPackedRadius, 0.01,
                    0.1 * kPackedRadius, sheet, D == 2 ? 1e-4 : 0.0);
  w.spars.flags.back() |= kNodeDriven;
  w.sort_interval = 3;
  w.one_slab = true;
  return w;
}

// `touching`: the grain-chain contacts at step 100 (counted over all ranks).
template <int D>
void advance(World<D>& w, int from, int to, std::size_t* touching = nullptr) {
  for (int k = from; k < to; ++k) {
    if (k == 100) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);  // the floor slides
    if (k == kPull) w.spars.vel.back() = vec<D>(D == 2 ? 1.0 : 0.3, 0.0, 0.0);
    w.measure_this_step = k + 1 == kSteps || k + 1 == 100;
    step(w);
    if (touching && k + 1 == 100) *touching = w.stats.spar_contacts;
  }
}

// Every node's position and velocity, the same on every rank.
template <int D>
void expect_same_nodes(const World<D>& a, const World<D>& b) {
  ASSERT_EQ(a.spars.nodes(), b.spars.nodes());
  for (std::size_t i = 0; i < a.spars.nodes(); ++i)
    ASSERT_TRUE(a.spars.pos[i] == b.spars.pos[i] && a.spars.vel[i] == b.spars.vel[i])
        << "node " << i;
  for (std::size_t e = 0; e < a.spars.elements(); ++e)
    ASSERT_EQ(a.spars.tension[e], b.spars.tension[e]) << "element " << e;
}

template <int D>
std::vector<World<D>> on_ranks(int ranks, std::vector<Sums<D>>& sums, std::uint64_t& migrated,
                               std::size_t& touching) {
  Hub hub(ranks);
  std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
  std::vector<std::uint64_t> moved(parts.size(), 0);
  std::vector<std::size_t> spar_contacts(parts.size(), 0);
  sums.assign(parts.size(), Sums<D>{});
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      const auto ur = static_cast<std::size_t>(r);
      auto& w = parts[ur];
      w = packing_with_chain<D>();
      auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
      // The cuts stay where distributed: the crossings asserted below happen at them (moved by
      // measured times, they may fall where no grain crosses; domain_test.cpp moves them).
      d->rebalance_every = 0;
      advance(w, 0, kSteps, &spar_contacts[ur]);
      sums[ur] = sums_of(w);
      moved[ur] = d->migrated();
    });
  for (auto& t : threads) t.join();
  migrated = 0;
  for (auto m : moved) migrated += m;
  touching = spar_contacts[0];
  return parts;
}

template <typename T>
class DomainSparsTest : public ::testing::Test {};
TYPED_TEST_SUITE(DomainSparsTest, Dims, DimNames);

TYPED_TEST(DomainSparsTest, RanksGiveTheBitsOfOneRank) {
  constexpr int D = TypeParam::value;
  std::vector<Sums<D>> one_sums, sums;
  std::uint64_t migrated = 0;
  std::size_t touching = 0;
  const auto one = on_ranks<D>(1, one_sums, migrated, touching);
  const std::size_t ids = one[0].particles.next_id;
  std::size_t ghosts = 0;
  const auto reference = by_id(one, ids, ghosts);
  EXPECT_GT(touching, 20u) << "too few grains touch the chain";
  const auto& T = one[0].spars.tension;
  EXPECT_GT(*std::max_element(T.begin(), T.end()), 0.0) << "the chain is not loaded";
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(::testing::Message() << ranks << " ranks");
    const auto parts = on_ranks<D>(ranks, sums, migrated, touching);
    expect_same<D>(by_id(parts, ids, ghosts), reference);
    for (const auto& w : parts) {
      expect_same_nodes<D>(w, one[0]);
      EXPECT_EQ(w.dt, one[0].dt);
      EXPECT_EQ(w.stats.spar_contacts, one[0].stats.spar_contacts);
    }
    for (const auto& s : sums) expect_sums<D>(s, one_sums[0], 0.0);
    EXPECT_GT(migrated, 0u);
  }
}

// A checkpoint of 3 ranks at step 900 (the chains whole, the grain-spar springs as records)
// resumed on 2 and on 1 rank: the bits of the uninterrupted run.
TYPED_TEST(DomainSparsTest, ACheckpointResumesOnOtherRankCounts) {
  constexpr int D = TypeParam::value;
  constexpr int kCut = 900;
  std::vector<Sums<D>> sums;
  std::uint64_t migrated = 0;
  std::size_t touching = 0;
  const auto uninterrupted = on_ranks<D>(3, sums, migrated, touching);
  const std::size_t ids = uninterrupted[0].particles.next_id;
  std::size_t ghosts = 0;
  const auto reference = by_id(uninterrupted, ids, ghosts);
  const SavedDomain saved = checkpoint_on_ranks<D>(
      3, [] { return packing_with_chain<D>(); }, [](World<D>& w) { advance(w, 0, kCut); });
  EXPECT_GT(saved.spars, 0u);
  for (int ranks : {2, 1}) {
    SCOPED_TRACE(::testing::Message() << "resumed on " << ranks << " ranks");
    const auto parts = resume_on_ranks<D>(
        ranks, saved, [] { return packing_with_chain<D>(); },
        [](World<D>& w) { advance(w, kCut, kSteps); });
    expect_same<D>(by_id(parts, ids, ghosts), reference);
    for (const auto& w : parts) expect_same_nodes<D>(w, uninterrupted[0]);
  }
}

}  // namespace
}  // namespace geodem::test
