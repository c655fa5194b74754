// Results do not depend on the thread count (base/parallel.hpp): the same packing run
// with 1, 2 and 3 threads ends in bitwise the same state. The packing is large enough
// for every stage to run in parallel (several force slabs, parallel integration), it
// starts overlapping so that grains move and the list is rebuilt and renumbered often,
// its floor slides, the stress is measured along the way, and the automatic time step
// is updated every 10 steps. One variant carries rolling springs and bonds (the force
// stage's other instantiation). A sheared periodic cell of colliding grains takes the
// cell's path: its parallel search, renumbering in the cell, and the cell's sums. A crowd
// of three-grain clumps thrown together takes the clump integration's parallel loops. The
// grains moved slab by slab in the force stage give the bits of the move's own pass. A
// smaller packing runs its slabs on threads and its per-grain loops on one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <random>

#include "base/parallel.hpp"
#include "clumps/clump_dynamics.hpp"
#include "clumps/clump_template.hpp"
#include "moving_worlds.hpp"
#include "pressed_packing.hpp"

namespace geodem::test {
namespace {

template <typename T>
class ThreadDeterminism : public ::testing::Test {};
TYPED_TEST_SUITE(ThreadDeterminism, Dims, DimNames);

template <int D>
World<D> make_packing(bool extras, int threads, std::size_t n = 12000) {
  World<D> w = pressed_packing<D>(extras, n, D == 2 ? 100 : 22, 40.0, 11);
  w.threads = threads;
  return w;
}

// A controller that changes nothing and counts the steps on which the force stage had already
// moved the grains when it ran (world/step.cpp); one of grains (not walls_only) forbids that.
template <int D>
class MoveProbe : public Controller<D> {
 public:
  MoveProbe(bool walls_only, int& moved) : walls_only_(walls_only), moved_(moved) {}
  void apply(World<D>& w) override { moved_ += w.grains_moved ? 1 : 0; }
  bool walls_only() const override { return walls_only_; }

 private:
  bool walls_only_;
  int& moved_;
};

template <int D>
World<D> run(bool extras, int threads, std::shared_ptr<Controller<D>> probe = nullptr,
             std::size_t n = 12000) {
  World<D> w = make_packing<D>(extras, threads, n);
  if (probe) w.controllers.push_back(probe);
  for (int k = 0; k < 400; ++k) {
    if (k == 100) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);  // the floor slides
    w.measure_this_step = k % 25 == 0;
    step(w);
  }
  return w;
}

template <int D>
void expect_identical(const World<D>& a, const World<D>& b, int threads) {
  SCOPED_TRACE(::testing::Message() << threads << " threads against 1");
  EXPECT_TRUE(same_bits(a.particles.pos, b.particles.pos));
  EXPECT_TRUE(same_bits(a.particles.vel, b.particles.vel));
  EXPECT_TRUE(same_bits(a.particles.angvel, b.particles.angvel));
  EXPECT_TRUE(same_bits(a.particles.id, b.particles.id));  // the same renumbering
  EXPECT_TRUE(same_bits(a.nlist.spring, b.nlist.spring));
  for (std::size_t k = 0; k < a.walls.size(); ++k) {
    EXPECT_TRUE(a.walls[k].force == b.walls[k].force) << "wall " << k;
    EXPECT_EQ(a.walls[k].stiffness, b.walls[k].stiffness) << "wall " << k;
  }
  EXPECT_TRUE(a.stats.fabric_stress == b.stats.fabric_stress);
  EXPECT_EQ(a.stats.sum_force, b.stats.sum_force);
  EXPECT_EQ(a.broken_bonds, b.broken_bonds);
  EXPECT_EQ(a.dt, b.dt);
  // Measurements are sums over grains in fixed blocks, taken on each world's own threads.
  EXPECT_EQ(kinetic_energy(a), kinetic_energy(b));
  EXPECT_EQ(solid_volume(a), solid_volume(b));
  EXPECT_EQ(gravity_energy(a), gravity_energy(b));
  EXPECT_EQ(unbalanced_force_ratio(a), unbalanced_force_ratio(b));
}

TYPED_TEST(ThreadDeterminism, OneTwoAndThreeThreadsGiveTheSameBits) {
  constexpr int D = TypeParam::value;
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  for (bool extras : {false, true}) {
    SCOPED_TRACE(extras ? "rolling springs and bonds" : "frictional");
    const World<D> one = run<D>(extras, 1);
    // The case exercises what it claims: several slabs, moving grains, rebuilds.
    ASSERT_GT(one.particles.size(), 2 * kParallelMin);  // three slabs or more
    EXPECT_GE(one.nlist.builds, 4u);  // renumbered at builds 0 and 3 (sort_interval)
    EXPECT_GT(one.stats.contacts, one.particles.size());
    if (extras) {
      EXPECT_GT(one.broken_bonds, 0u);
    }
    for (int threads : {2, 3}) expect_identical(one, run<D>(extras, threads), threads);
  }
}

TYPED_TEST(ThreadDeterminism, SlabsOnThreadsWithSerialGrainLoopsGiveTheSameBits) {
  // Between kParallelSlabsMin and kParallelMin grains the force stage's slabs and the crossing
  // forces go to threads while the per-grain loops stay on one: the mixed path of a 2D pull-out.
  constexpr int D = TypeParam::value;
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  constexpr std::size_t n = 3000;
  static_assert(n >= kParallelSlabsMin && n < kParallelMin);
  const World<D> one = run<D>(false, 1, nullptr, n);
  ASSERT_EQ(one.particles.size(), n);
  EXPECT_GE(one.nlist.builds, 4u);
  // The grains press on each other (the 3D bed is six layers deep: half a contact a grain).
  EXPECT_GT(2 * one.stats.contacts, one.particles.size());
  for (int threads : {2, 3}) expect_identical(one, run<D>(false, threads, nullptr, n), threads);
}

TYPED_TEST(ThreadDeterminism, MovingGrainsInTheForceStageGivesTheSameBits) {
  // The step moves each slab's grains as soon as their forces are complete when only wall
  // controllers run in between; a controller of grains makes it move them in a pass of their
  // own after the controllers. The same bits either way, on any thread count.
  constexpr int D = TypeParam::value;
  for (bool extras : {false, true}) {
    SCOPED_TRACE(extras ? "rolling springs and bonds" : "frictional");
    for (int threads : {1, 3}) {
      int early = 0, late = 0;
      const World<D> fused = run<D>(extras, threads, std::make_shared<MoveProbe<D>>(true, early));
      const World<D> apart = run<D>(extras, threads, std::make_shared<MoveProbe<D>>(false, late));
      EXPECT_EQ(early, 400);  // moved in the force stage on every step
      EXPECT_EQ(late, 0);
      expect_identical(apart, fused, threads);
    }
  }
}

template <int D>
World<D> run_periodic(int threads) {
  World<D> w = sheared_cell<D>(D == 2 ? 100 : 22);
  w.threads = threads;
  for (int k = 0; k < 300; ++k) {
    w.measure_this_step = k % 25 == 0;
    step(w);
  }
  return w;
}

TYPED_TEST(ThreadDeterminism, PeriodicCellGivesTheSameBitsOnOneTwoAndThreeThreads) {
  constexpr int D = TypeParam::value;
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  const World<D> one = run_periodic<D>(1);
  ASSERT_GT(one.particles.size(), 2 * kParallelMin);
  EXPECT_GE(one.nlist.builds, 3u);  // renumbered in the cell at builds 0 and 2
  EXPECT_GT(one.stats.contacts, 0u);
  for (int threads : {2, 3}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads against 1");
    const World<D> other = run_periodic<D>(threads);
    expect_same_grains(one, other);
    EXPECT_TRUE(same_bits(one.nlist.image, other.nlist.image));
    EXPECT_TRUE(one.cell.h == other.cell.h);
    EXPECT_TRUE(one.cell_fabric == other.cell_fabric);
    EXPECT_TRUE(one.cell_stiffness == other.cell_stiffness);
  }
}

template <int D>
World<D> run_clumps(int threads) {
  World<D> w = colliding_clumps<D>(
      D == 2 ? std::array<int, 3>{64, 48, 1} : std::array<int, 3>{14, 14, 14}, 1.0);
  w.threads = threads;
  for (int k = 0; k < 1000; ++k) {
    w.measure_this_step = k % 25 == 0;
    step(w);
  }
  return w;
}

TYPED_TEST(ThreadDeterminism, ClumpsGiveTheSameBitsOnOneTwoAndThreeThreads) {
  constexpr int D = TypeParam::value;
  if (!built_with_openmp()) GTEST_SKIP() << "built without OpenMP";
  const World<D> one = run_clumps<D>(1);
  ASSERT_GE(one.clumps.size(), kParallelMin / 2);  // the clump loops run in parallel
  EXPECT_GE(one.nlist.builds, 3u);
  EXPECT_GT(one.stats.contacts, 100u);  // the clumps collided
  for (int threads : {2, 3}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads against 1");
    const World<D> other = run_clumps<D>(threads);
    expect_same_grains(one, other);
    EXPECT_TRUE(same_bits(one.clumps.pos, other.clumps.pos));
    EXPECT_TRUE(same_bits(one.clumps.vel, other.clumps.vel));
    EXPECT_TRUE(same_bits(one.clumps.angvel, other.clumps.angvel));
    EXPECT_TRUE(same_bits(one.clumps.orient, other.clumps.orient));
    EXPECT_TRUE(one.stats.fabric_stress == other.stats.fabric_stress);
  }
}

}  // namespace
}  // namespace geodem::test
