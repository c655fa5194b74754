// Clumps in a decomposed domain (domain/slab_clumps.cpp): a clump belongs to the rank of its
// centre with all its members, ghost members bring a ghost clump that names their body, and a
// clump whose centre crosses a cut moves with its members. Pair clumps and discs thrown
// together in a box, with bonds and rolling friction or without, a band excavated halfway, a
// layer of clumps and discs added by every rank alike (each keeps its own), the radii grown by
// steps for a while (as the triaxial compaction grows them):
// 1, 2 and 3 ranks end in the same bits, grains and clumps, and with grains in id order in the
// bits of one process; a checkpoint of 3 ranks resumes on 2 and 1 with the uninterrupted bits.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <thread>

#include "clumps/clump_template.hpp"
#include "contacts/bonds.hpp"
#include "controllers/radius_growth.hpp"
#include "domain_ranks.hpp"
#include "world/world_editing.hpp"

namespace geodem::test {
namespace {

constexpr double kR = 1e-3, kRho = 2600.0;
constexpr int kSteps = 1200, kExcavation = 600, kLayer = 700;

// Pair clumps (two members of radius kR, lying along x, turned by up to 0.02 rad) and discs
// in rows 0.1 kR apart in a box under gravity, each body given a random velocity (they
// collide at once); the automatic time step every 10 steps and keys retaken every 3 list
// builds (0: grains kept in id order). With `bonds`: rolling friction and bonds between bodies
// less than 0.3 kR apart (most neighbours in the rows).
template <int D>
World<D> clump_packing(bool bonds, int sort_interval) {
  World<D> w;
  const double kn = kRho * Dim<D>::volume(kR) * 9.81 / (1e-4 * kR);
  Material gm = linear_material(kn, 0.5 * kn, 0.5, 0.3, kRho);
  if (bonds) {
    gm.rolling_friction = 0.2;
    const double section = D == 2 ? 2.0 * kR : 3.14159 * kR * kR;
    gm.normal_cohesion = gm.shear_cohesion = 2e-3 * kn / section;
  }
  const auto grain = add_material(w, gm);
  const auto wall = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 0.3, kRho, "wall"));
  const Vec<D> spacing = vec<D>(4.1, 2.1, 2.1) * kR;
  const std::array<int, 3> n{D == 2 ? 36 : 14, D == 2 ? 16 : 6, D == 2 ? 1 : 6};
  Vec<D> hi = vec<D>(n[0], 2 * n[1], n[2]).cwiseProduct(spacing);
  add_box(w, Vec<D>(Vec<D>::Zero()), hi, wall, wall);
  w.resolve_pair_laws();
  ClumpTemplate<D> t;
  builtin_clump_template("pair", t);
  const ResolvedClump<D> pair = resolve_clump(t);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int j = 0; j < n[1]; ++j)
    for (int l = 0; l < n[2]; ++l)
      for (int i = 0; i < n[0]; ++i) {
        const Vec<D> x = vec<D>(i + 0.5, j + 0.5, l + 0.5).cwiseProduct(spacing);
        Vec<D> v;
        for (int k = 0; k < D; ++k) v[k] = 0.3 * u(rng);
        if ((i + j + l) % 3 == 0) {
          w.particles.add(x, kR * (0.9 + 0.1 * u(rng)), kRho, grain, v);
          continue;
        }
        typename Dim<D>::Orient q;
        if constexpr (D == 2)
          q = 0.02 * u(rng);
        else
          q = Eigen::Quaterniond(Eigen::AngleAxisd(0.02 * u(rng), Vec<D>(0.0, 0.6, 0.8)));
        add_clump(w, pair, x, q, kR, kRho, grain, v);
      }
  if (bonds) create_bonds(w, 0.3);
  w.gravity = vec<D>(0.0, -9.81, 0.0);
  w.auto_dt = true;
  w.dt_safety = 0.3;
  w.dt_update_interval = 10;
  w.sort_interval = sort_interval;
  w.one_slab = true;
  return w;
}

// A layer of pair clumps and discs added above the packing, by every rank alike (as a stage's
// cloud): a decomposed world keeps each rank's own (SlabDomain::grains_added).
template <int D>
void add_layer(World<D>& w) {
  const std::size_t grains = w.particles.size(), clumps = w.clumps.size();
  ClumpTemplate<D> t;
  builtin_clump_template("pair", t);
  const ResolvedClump<D> pair = resolve_clump(t);
  const int across = D == 2 ? 36 : 14, deep = D == 2 ? 1 : 6;
  for (int i = 0; i < across; ++i)
    for (int l = 0; l < deep; ++l) {
      // (the second row below the lid: the box is twice the packing's rows high)
      const double row = D == 2 ? 30.5 : 10.5;
      const Vec<D> x = vec<D>(i + 0.5, row, l + 0.5).cwiseProduct(vec<D>(4.1, 2.1, 2.1) * kR);
      if (i % 2 == 0) {
        add_clump(w, pair, x, typename Dim<D>::Orient(Dim<D>::identity()), kR, kRho,
                  std::uint16_t{0}, vec<D>(0.0, -0.5, 0.0));
      } else {
        w.particles.add(x, 1.2 * kR, kRho, 0, vec<D>(0.0, -0.5, 0.0));
      }
    }
  if (w.domain)
    dynamic_cast<SlabDomain<D>&>(*w.domain).grains_added(w, grains, clumps);
  else
    add_list_rows_for_new_grains(w, grains);
}

// Steps from..to: the floor slides from step 100, a band across the box is excavated (whole
// clumps with any member in it) at kExcavation, a layer falls in from above at kLayer, the
// last step measures.
template <int D>
void advance(World<D>& w, int from, int to) {
  for (int k = from; k < to; ++k) {
    if (k == 100) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);
    // Radius growth (as the triaxial compaction's): members' offsets, masses and inertias
    // grow on every rank alike, the ghost width with them.
    if (k >= 150 && k < 250 && k % 10 == 0) RadiusGrowth<D>::scale(w, 1.001);
    if (k == kLayer) add_layer(w);
    if (k == kExcavation) {
      const auto& P = w.particles;
      remove_grains(w,
                    grains_where(w,
                                 [&](std::size_t i) {
                                   return P.pos[i].y() > 6.0 * 2.1 * kR &&
                                          P.pos[i].y() < 9.0 * 2.1 * kR;
                                 }),
                    ContactHistory::kKeep);
    }
    w.measure_this_step = k + 1 == kSteps;
    step(w);
  }
}

// A clump's state by id, from its owner.
template <int D>
struct ClumpState {
  typename Dim<D>::Vec pos, vel;
  typename Dim<D>::Rot angvel;
  typename Dim<D>::Orient orient;
  bool seen = false;
};
template <int D>
std::map<std::uint32_t, ClumpState<D>> clumps_by_id(const std::vector<World<D>>& parts) {
  std::map<std::uint32_t, ClumpState<D>> out;
  for (const auto& w : parts) {
    const auto& C = w.clumps;
    for (std::size_t c = 0; c < C.owned(); ++c) {
      EXPECT_FALSE(out[C.id[c]].seen) << "clump " << C.id[c] << " owned twice";
      out[C.id[c]] = {C.pos[c], C.vel[c], C.angvel[c], C.orient[c], true};
    }
  }
  return out;
}
template <int D>
void expect_same_clumps(const std::map<std::uint32_t, ClumpState<D>>& a,
                        const std::map<std::uint32_t, ClumpState<D>>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [id, s] : a) {
    const auto it = b.find(id);
    ASSERT_TRUE(it != b.end()) << "clump " << id;
    const auto& t = it->second;
    ASSERT_TRUE(s.pos == t.pos && s.vel == t.vel && s.angvel == t.angvel) << "clump " << id;
    if constexpr (D == 2)
      ASSERT_EQ(s.orient, t.orient) << "clump " << id;
    else
      ASSERT_TRUE(s.orient.coeffs() == t.orient.coeffs()) << "clump " << id;
  }
}

// What a run on `ranks` ranks shows besides the states.
struct Seen {
  std::uint64_t migrated = 0;       // grains that changed ranks
  std::size_t ghost_clumps = 0;     // at the end, all ranks
  std::size_t members_outside = 0;  // owned members whose centre is outside the rank's slab
};

template <int D>
std::vector<World<D>> on_ranks(bool bonds, int sort_interval, int ranks, std::vector<Sums<D>>& sums,
                               Seen& seen) {
  Hub hub(ranks);
  std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
  std::vector<Seen> each(parts.size());
  sums.assign(parts.size(), Sums<D>{});
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      const auto ur = static_cast<std::size_t>(r);
      auto& w = parts[ur];
      w = clump_packing<D>(bonds, sort_interval);
      auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
      // The cuts stay where distributed: the crossings asserted below happen at them (moved by
      // measured times, they may fall where no grain crosses; domain_test.cpp moves them).
      d->rebalance_every = 0;
      advance(w, 0, kSteps);
      sums[ur] = sums_of(w);
      each[ur].migrated = d->migrated();
      each[ur].ghost_clumps = w.clumps.ghosts;
      const auto& P = w.particles;
      for (std::size_t i = 0; i < P.size(); ++i)
        if (P.member(i) && !(P.flags[i] & kGhost) &&
            (P.pos[i].x() < d->cuts()[ur] || P.pos[i].x() >= d->cuts()[ur + 1]))
          ++each[ur].members_outside;
    });
  for (auto& t : threads) t.join();
  seen = {};
  for (const auto& e : each) {
    seen.migrated += e.migrated;
    seen.ghost_clumps += e.ghost_clumps;
    seen.members_outside += e.members_outside;
  }
  return parts;
}

template <int D>
std::size_t grains_of(const std::vector<World<D>>& parts) {
  std::size_t n = 0;
  for (const auto& w : parts) n += w.particles.size();
  return n - ghosts_in(parts);
}

template <typename T>
class DomainClumpsTest : public ::testing::Test {};
TYPED_TEST_SUITE(DomainClumpsTest, Dims, DimNames);

TYPED_TEST(DomainClumpsTest, RanksGiveTheBitsOfOneRank) {
  constexpr int D = TypeParam::value;
  for (bool bonds : {false, true}) {
    SCOPED_TRACE(bonds ? "bonds and rolling friction" : "frictional");
    std::vector<Sums<D>> one_sums, sums;
    Seen seen;
    const auto one = on_ranks<D>(bonds, 3, 1, one_sums, seen);
    const std::size_t n = grains_of(one);
    std::size_t ghosts = 0;
    const auto reference = by_id(one, one[0].particles.next_id, ghosts);
    const auto reference_clumps = clumps_by_id(one);
    EXPECT_LT(n, one[0].particles.next_id) << "the excavation removed nothing";
    EXPECT_EQ(one[0].particles.next_id, D == 2 ? 1014u : 966u) << "the layer was not added";
    EXPECT_GT(reference_clumps.size(), n / 3);
    if (bonds) {
      EXPECT_GT(one_sums[0].bonds, 0u);
    }
    for (int ranks : {2, 3}) {
      SCOPED_TRACE(::testing::Message() << ranks << " ranks");
      const auto parts = on_ranks<D>(bonds, 3, ranks, sums, seen);
      EXPECT_EQ(grains_of(parts), n);
      expect_same<D>(by_id(parts, one[0].particles.next_id, ghosts), reference);
      expect_same_clumps<D>(clumps_by_id(parts), reference_clumps);
      for (const auto& w : parts) EXPECT_EQ(w.dt, one[0].dt);
      for (const auto& s : sums) expect_sums<D>(s, one_sums[0], 0.0);
      EXPECT_GT(seen.migrated, 0u) << "no grain changed rank";
      EXPECT_GT(seen.ghost_clumps, 0u);
      EXPECT_GT(seen.members_outside, 0u) << "no member lay across a cut from its clump";
    }
  }
}

// Grains in id order: the domain's runs are the one-process run (no renumbering there either).
TYPED_TEST(DomainClumpsTest, ThreeRanksGiveTheBitsOfOneProcess) {
  constexpr int D = TypeParam::value;
  World<D> one = clump_packing<D>(true, 0);
  advance(one, 0, kSteps);
  std::vector<World<D>> single(1);
  single[0] = std::move(one);
  std::vector<Sums<D>> sums;
  Seen seen;
  const auto parts = on_ranks<D>(true, 0, 3, sums, seen);
  std::size_t ghosts = 0;
  const std::size_t ids = single[0].particles.next_id;
  expect_same<D>(by_id(parts, ids, ghosts), by_id(single, ids, ghosts));
  expect_same_clumps<D>(clumps_by_id(parts), clumps_by_id(single));
  for (const auto& w : parts) EXPECT_EQ(w.dt, single[0].dt);
  // The measurements (the stress with clump centres for members' included) agree with the one
  // process's, which sums in its own order, to 1e-12.
  for (const auto& s : sums) expect_sums<D>(s, sums_of(single[0]), 1e-12);
}

// A checkpoint of 3 ranks at step 900 (the whole domain on rank 0: grains in key order, clumps
// in id order) resumed on 2 and on 1 rank: the bits of the uninterrupted run.
TYPED_TEST(DomainClumpsTest, ACheckpointResumesOnOtherRankCounts) {
  constexpr int D = TypeParam::value;
  constexpr int kCut = 900;
  std::vector<Sums<D>> sums;
  Seen seen;
  const auto uninterrupted = on_ranks<D>(true, 3, 3, sums, seen);
  const std::size_t ids = uninterrupted[0].particles.next_id;
  std::size_t ghosts = 0;
  const auto reference = by_id(uninterrupted, ids, ghosts);
  const auto reference_clumps = clumps_by_id(uninterrupted);
  const SavedDomain saved = checkpoint_on_ranks<D>(
      3, [] { return clump_packing<D>(true, 3); }, [](World<D>& w) { advance(w, 0, kCut); });
  EXPECT_GT(saved.clumps, 0u);
  EXPECT_EQ(saved.clump_ghosts, 0u);
  for (int ranks : {2, 1}) {
    SCOPED_TRACE(::testing::Message() << "resumed on " << ranks << " ranks");
    const auto parts = resume_on_ranks<D>(
        ranks, saved, [] { return clump_packing<D>(true, 3); },
        [](World<D>& w) { advance(w, kCut, kSteps); });
    expect_same<D>(by_id(parts, ids, ghosts), reference);
    expect_same_clumps<D>(clumps_by_id(parts), reference_clumps);
  }
}

}  // namespace
}  // namespace geodem::test
