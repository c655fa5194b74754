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

#include "domain/slab_domain.hpp"
#include "measure/measurements.hpp"
#include "pressed_packing.hpp"
#include "world/world_editing.hpp"
#include "world/world_state.hpp"

namespace geodem::test {
namespace {

// Messages between `size` threads: each call is a collective step all of them take.
struct Hub {
  explicit Hub(int n) : size(n), sync(n), down(n), up(n), values(n), sums(n), gathered(n) {}
  int size;
  std::barrier<> sync;
  std::vector<Bytes> down, up;
  std::vector<double> values;
  std::vector<std::vector<ExactSum>> sums;
  std::vector<Bytes> gathered;
};

class ThreadComm final : public DomainComm {
 public:
  ThreadComm(Hub& hub, int rank) : hub_(hub), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return hub_.size; }
  void exchange(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                Bytes& from_upper) override {
    const auto r = static_cast<std::size_t>(rank_);
    hub_.down[r] = to_lower, hub_.up[r] = to_upper;
    hub_.sync.arrive_and_wait();
    from_lower = rank_ > 0 ? hub_.up[r - 1] : Bytes{};
    from_upper = rank_ + 1 < hub_.size ? hub_.down[r + 1] : Bytes{};
    hub_.sync.arrive_and_wait();
  }
  double max(double here) override { return reduce(here, true); }
  double min(double here) override { return reduce(here, false); }
  void sum(std::vector<ExactSum>& sums) override {
    hub_.sums[static_cast<std::size_t>(rank_)] = sums;
    hub_.sync.arrive_and_wait();
    for (std::size_t k = 0; k < sums.size(); ++k) {
      ExactSum total;
      for (const auto& s : hub_.sums) total.add(s[k]);
      sums[k] = total;
    }
    hub_.sync.arrive_and_wait();
  }
  Bytes gather(const Bytes& here) override {
    Bytes all = all_gather(here);
    return rank_ == 0 ? all : Bytes{};
  }
  Bytes all_gather(const Bytes& here) override {
    hub_.gathered[static_cast<std::size_t>(rank_)] = here;
    hub_.sync.arrive_and_wait();
    Bytes all;
    for (const auto& b : hub_.gathered) all.insert(all.end(), b.begin(), b.end());
    hub_.sync.arrive_and_wait();
    return all;
  }

 private:
  double reduce(double here, bool largest) {
    hub_.values[static_cast<std::size_t>(rank_)] = here;
    hub_.sync.arrive_and_wait();
    const auto [lo, hi] = std::minmax_element(hub_.values.begin(), hub_.values.end());
    const double v = largest ? *hi : *lo;
    hub_.sync.arrive_and_wait();
    return v;
  }
  Hub& hub_;
  int rank_;
};

template <int D>
World<D> packing(bool extras, int sort_interval) {
  World<D> w = pressed_packing<D>(extras, D == 2 ? 6000 : 4000, D == 2 ? 80 : 16, 40.0, 5);
  w.sort_interval = sort_interval;
  w.one_slab = true;
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

// What the contact stage summed over the whole domain: the walls' forces, stiffnesses and
// the contact statistics of the last step; and the measurements over the grains.
template <int D>
struct Sums {
  std::vector<typename Dim<D>::Vec> force;
  std::vector<double> stiffness;
  typename Dim<D>::Tensor fabric;
  double sum_force, energy;
  std::size_t contacts, wall_contacts;
  // Measurements (measure/measurements.hpp), over the whole domain on every rank.
  double kinetic, unbalanced, volume, gravity;
  std::size_t bodies, bonds;
};
template <int D>
Sums<D> sums_of(const World<D>& w) {
  Sums<D> s{{},
            {},
            w.stats.fabric_stress,
            w.stats.sum_force,
            w.stats.elastic_energy,
            w.stats.contacts,
            w.stats.wall_contacts,
            kinetic_energy(w),
            unbalanced_force_ratio(w),
            solid_volume(w),
            gravity_energy(w),
            body_count(w),
            intact_bonds(w)};
  for (const auto& wall : w.walls)
    s.force.push_back(wall.force), s.stiffness.push_back(wall.stiffness);
  return s;
}
// Bitwise (exact sums of ranks) or within `rel` of the largest component (a one-process run
// sums in its own order).
template <int D>
void expect_sums(const Sums<D>& a, const Sums<D>& b, double rel) {
  auto near = [rel](double x, double y, double scale) {
    return rel == 0.0 ? x == y : std::abs(x - y) <= rel * scale;
  };
  for (std::size_t k = 0; k < a.force.size(); ++k) {
    const double scale = a.force[k].cwiseAbs().maxCoeff() + 1e-300;
    for (int c = 0; c < D; ++c)
      EXPECT_TRUE(near(a.force[k][c], b.force[k][c], scale))
          << "wall " << k << ": " << a.force[k][c] << " against " << b.force[k][c];
    EXPECT_TRUE(near(a.stiffness[k], b.stiffness[k], a.stiffness[k])) << "wall " << k;
  }
  const double fs = a.fabric.cwiseAbs().maxCoeff();
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < D; ++c) EXPECT_TRUE(near(a.fabric(r, c), b.fabric(r, c), fs));
  EXPECT_TRUE(near(a.sum_force, b.sum_force, a.sum_force));
  EXPECT_TRUE(near(a.energy, b.energy, a.energy));
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.wall_contacts, b.wall_contacts);
  EXPECT_TRUE(near(a.kinetic, b.kinetic, a.kinetic));
  EXPECT_TRUE(near(a.unbalanced, b.unbalanced, a.unbalanced));
  EXPECT_TRUE(near(a.volume, b.volume, a.volume));
  EXPECT_TRUE(near(a.gravity, b.gravity, std::abs(a.gravity)));
  EXPECT_EQ(a.bodies, b.bodies);
  EXPECT_EQ(a.bonds, b.bonds);
}

// The packing advanced on `ranks` ranks (threads); also says whether grains changed ranks,
// and gives each rank's sums (taken on the ranks: they are collective).
template <int D>
std::vector<World<D>> on_ranks(bool extras, int sort_interval, int ranks, bool& moved,
                               std::vector<Sums<D>>& sums, int rebalance_every = 10,
                               bool* cuts_moved = nullptr) {
  Hub hub(ranks);
  std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
  std::vector<std::uint64_t> migrated(parts.size(), 0);
  sums.assign(parts.size(), Sums<D>{});
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      auto& w = parts[static_cast<std::size_t>(r)];
      w = packing<D>(extras, sort_interval);
      auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
      d->rebalance_every = rebalance_every;
      d->rebalance_tolerance = 0.0;  // move whenever the times differ
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

// Every grain's state by id, from its owner: the grains of all ranks in one table.
template <int D>
struct Grain {
  typename Dim<D>::Vec pos, vel;
  typename Dim<D>::Rot angvel;
  bool seen = false;
};
template <int D>
std::vector<Grain<D>> by_id(const std::vector<World<D>>& parts, std::size_t n,
                            std::size_t& ghosts) {
  std::vector<Grain<D>> g(n);
  ghosts = 0;
  for (const auto& w : parts) {
    const auto& P = w.particles;
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.flags[i] & kGhost) {
        ++ghosts;
        continue;
      }
      EXPECT_FALSE(g[P.id[i]].seen) << "grain " << P.id[i] << " owned twice";
      g[P.id[i]] = {P.pos[i], P.vel[i], P.angvel[i], true};
    }
  }
  return g;
}

template <int D>
std::size_t ghosts_in(const std::vector<World<D>>& parts) {
  std::size_t g = 0;
  for (const auto& w : parts)
    for (auto f : w.particles.flags) g += (f & kGhost) != 0;
  return g;
}

template <int D>
void expect_same(const std::vector<Grain<D>>& a, const std::vector<Grain<D>>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_TRUE(a[k].seen && b[k].seen) << "grain " << k << " not owned";
    ASSERT_TRUE(a[k].pos == b[k].pos) << "grain " << k;
    ASSERT_TRUE(a[k].vel == b[k].vel) << "grain " << k;
    ASSERT_TRUE(a[k].angvel == b[k].angvel) << "grain " << k;
  }
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
// bits, grains and the domain's sums, and the ranks' grains did leave id order.
TYPED_TEST(DomainTest, RanksInCellOrderAgree) {
  constexpr int D = TypeParam::value;
  bool cuts_moved = false;  // in some of the runs (they follow measured times)
  for (bool extras : {false, true}) {
    SCOPED_TRACE(extras ? "rolling springs and bonds" : "frictional");
    bool moved = false;
    std::size_t ghosts = 0;
    std::vector<Sums<D>> one_sums, sums;
    const auto one = on_ranks<D>(extras, 3, 1, moved, one_sums);
    const std::size_t n = one[0].particles.size();
    EXPECT_FALSE(std::is_sorted(one[0].particles.id.begin(), one[0].particles.id.end()));
    const auto reference = by_id(one, n, ghosts);
    for (int ranks : {2, 3}) {
      SCOPED_TRACE(::testing::Message() << ranks << " ranks");
      bool moved_here = false;
      const auto parts = on_ranks<D>(extras, 3, ranks, moved, sums, 1, &moved_here);
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

// A checkpoint of a decomposed run (the whole domain gathered on rank 0 as one world, the
// contact history as records with the keys) resumed on another number of ranks goes on with
// the bits of the uninterrupted run: 3 ranks stopped at step 150, resumed on 2 and on 1.
TYPED_TEST(DomainTest, ACheckpointResumesOnOtherRankCounts) {
  constexpr int D = TypeParam::value;
  constexpr int kCut = 150;
  bool moved = false;
  std::size_t ghosts = 0;
  std::vector<Sums<D>> sums;
  const auto uninterrupted = on_ranks<D>(true, 3, 3, moved, sums, 0);
  std::size_t n = 0;
  for (const auto& w : uninterrupted) n += w.particles.size();
  n -= ghosts_in(uninterrupted);
  const auto reference = by_id(uninterrupted, n, ghosts);
  std::string world_bytes, domain_bytes;
  {
    Hub hub(3);
    std::vector<std::thread> threads;
    for (int r = 0; r < 3; ++r)
      threads.emplace_back([&, r] {
        World<D> w = packing<D>(true, 3);
        auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
        advance(w, 0, kCut);
        DomainCheckpoint<D> saved;
        Particles<D> all = d->checkpoint(w, saved);
        const std::uint64_t broken = broken_bond_count(w);
        if (r != 0) return;
        EXPECT_EQ(all.size(), n);
        EXPECT_FALSE(saved.pairs.empty());
        std::swap(w.particles, all);
        NeighbourList<D> none;
        w.nlist.swap_rows(none);
        w.broken_bonds = broken;
        StateWriter world_out, domain_out;
        save_world_state(world_out, w);
        saved.visit(domain_out);
        world_bytes = world_out.bytes(), domain_bytes = domain_out.bytes();
      });
    for (auto& t : threads) t.join();
  }
  for (int ranks : {2, 1}) {
    SCOPED_TRACE(::testing::Message() << "resumed on " << ranks << " ranks");
    Hub hub(ranks);
    std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
      threads.emplace_back([&, r] {
        auto& w = parts[static_cast<std::size_t>(r)];
        w = packing<D>(true, 3);
        StateReader world_in(world_bytes.data(), world_bytes.size());
        load_world_state(world_in, w);
        DomainCheckpoint<D> saved;
        StateReader domain_in(domain_bytes.data(), domain_bytes.size());
        saved.visit(domain_in);
        SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r), &saved);
        advance(w, kCut, kSteps);
      });
    for (auto& t : threads) t.join();
    expect_same<D>(by_id(parts, n, ghosts), reference);
    for (const auto& w : parts) EXPECT_EQ(w.dt, uninterrupted[0].dt);
  }
}

}  // namespace
}  // namespace geodem::test
