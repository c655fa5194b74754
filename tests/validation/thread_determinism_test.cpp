// Results do not depend on the thread count (base/parallel.hpp): the same packing run
// with 1, 2 and 3 threads ends in bitwise the same state. The packing is large enough
// for every stage to run in parallel (several force slabs, parallel integration), it
// starts overlapping so that grains move and the list is rebuilt and renumbered often,
// its floor slides, the stress is measured along the way, and the automatic time step
// is updated every 10 steps. One variant carries rolling springs and bonds (the force
// stage's other instantiation).
#include <gtest/gtest.h>

#include <cstring>

#include "base/parallel.hpp"
#include "pressed_packing.hpp"

namespace geodem::test {
namespace {

template <typename T>
class ThreadDeterminism : public ::testing::Test {};
TYPED_TEST_SUITE(ThreadDeterminism, Dims, DimNames);

template <int D>
World<D> make_packing(bool extras, int threads) {
  World<D> w = pressed_packing<D>(extras, 12000, D == 2 ? 100 : 22, 40.0, 11);
  w.threads = threads;
  return w;
}

template <int D>
World<D> run(bool extras, int threads) {
  World<D> w = make_packing<D>(extras, threads);
  for (int k = 0; k < 400; ++k) {
    if (k == 100) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);  // the floor slides
    w.measure_this_step = k % 25 == 0;
    step(w);
  }
  return w;
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
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

}  // namespace
}  // namespace geodem::test
