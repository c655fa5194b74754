// The two pieces that keep a large run's memory down without changing a bit of its results:
// the grains' arrays renumbered in place (Particles::permute, cycle by cycle) and the force
// stage's crossing buckets, whose blocks pass from slab to slab when the slabs run one after
// the other (SlabCrossings::recycle). Each is checked against the plain computation it
// replaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "base/parallel.hpp"
#include "particles/particles.hpp"

namespace geodem::test {
namespace {

Particles<3> numbered_grains(std::size_t n) {
  Particles<3> P;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = static_cast<double>(i);
    P.add(Eigen::Vector3d(x, 2.0 * x, -x), 0.5 + 1e-3 * x, 2500.0,
          static_cast<std::uint16_t>(i % 3), Eigen::Vector3d(-x, x, 0.5 * x));
    P.angvel.back() = Eigen::Vector3d(x, x + 1.0, x + 2.0);
    P.force.back() = Eigen::Vector3d(3.0 * x, 0.0, 1.0);
    P.pos_at_build.back() = Eigen::Vector3d(x, -x, 7.0);
  }
  return P;
}

void expect_grain(const Particles<3>& got, std::size_t k, const Particles<3>& was, std::size_t i) {
  ASSERT_EQ(got.pos[k], was.pos[i]) << k;
  ASSERT_EQ(got.vel[k], was.vel[i]) << k;
  ASSERT_EQ(got.angvel[k], was.angvel[i]) << k;
  ASSERT_EQ(got.force[k], was.force[i]) << k;
  ASSERT_EQ(got.radius[k], was.radius[i]) << k;
  ASSERT_EQ(got.inv_mass[k], was.inv_mass[i]) << k;
  ASSERT_EQ(got.inv_inertia[k], was.inv_inertia[i]) << k;
  ASSERT_EQ(got.material[k], was.material[i]) << k;
  ASSERT_EQ(got.id[k], was.id[i]) << k;
}

TEST(RenumberInPlace, EveryArrayFollowsTheOrderAndKeepsItsBuffer) {
  const std::size_t n = 2000;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 4; ++trial) {
    Particles<3> P = numbered_grains(n);
    const Particles<3> was = P;
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    if (trial == 1) {
      std::reverse(order.begin(), order.end());  // cycles of two
    } else if (trial == 2) {
      // nearly in order, as after a few steps of a settled bed: short local cycles
      for (std::size_t k = 0; k + 1 < n; k += 3) std::swap(order[k], order[k + 1]);
    } else if (trial == 3) {
      std::shuffle(order.begin(), order.end(), rng);  // long cycles
    }
    const auto* pos_buffer = P.pos.data();
    const auto* id_buffer = P.id.data();
    P.permute(order);
    ASSERT_EQ(P.size(), n);
    EXPECT_EQ(P.pos.data(), pos_buffer);  // in place: views of the arrays stay valid
    EXPECT_EQ(P.id.data(), id_buffer);
    for (std::size_t k = 0; k < n; ++k) {
      expect_grain(P, k, was, order[k]);
      ASSERT_EQ(P.pos_at_build[k], was.pos_at_build[order[k]]);
    }
  }
}

TEST(RenumberInPlace, ArraysGivenBackForABuildStayEmpty) {
  // The step gives the force, torque and build-position arrays back during a list build.
  Particles<3> P = numbered_grains(50);
  const Particles<3> was = P;
  std::vector<std::uint32_t> order(50);
  std::iota(order.rbegin(), order.rend(), 0u);
  std::vector<Eigen::Vector3d>().swap(P.force);
  std::vector<Eigen::Vector3d>().swap(P.torque);
  std::vector<Eigen::Vector3d>().swap(P.pos_at_build);
  P.permute(order);
  EXPECT_TRUE(P.force.empty());
  EXPECT_TRUE(P.torque.empty());
  EXPECT_TRUE(P.pos_at_build.empty());
  for (std::size_t k = 0; k < 50; ++k) ASSERT_EQ(P.pos[k], was.pos[49 - k]);
}

TEST(RenumberInPlace, ARemovalKeepsTheListedGrainsInOrder) {
  Particles<3> P = numbered_grains(30);
  const Particles<3> was = P;
  const std::vector<std::uint32_t> order = {29, 3, 4, 17, 0};
  P.permute(order);
  ASSERT_EQ(P.size(), order.size());
  for (std::size_t k = 0; k < order.size(); ++k) expect_grain(P, k, was, order[k]);
}

struct Entry {
  double value;
  std::uint32_t body;
};

// Every slab s sends entries to later slabs (s + 1 mostly, sometimes s + 2, a few to the
// bodies beyond the grains); returns, per target, the entries in the order apply_to() gives.
std::vector<std::vector<double>> crossings_received(bool recycle, int steps) {
  const std::size_t n = 8 * kMinSlab;
  const SlabPlan plan = SlabPlan::uniform(n, kMinSlab);
  SlabCrossings<Entry> crossings;
  std::vector<std::vector<double>> got;
  for (int step = 0; step < steps; ++step) {
    crossings.prepare(plan, 1);
    got.assign(plan.count + 1, {});
    for (std::size_t s = 0; s < plan.count; ++s) {
      auto w = crossings.slab(s);
      const std::size_t count = 100 + 37 * s + static_cast<std::size_t>(step) * 11;
      for (std::size_t e = 0; e < count; ++e) {
        std::size_t body = plan.last(s) + e % kMinSlab;  // next slab
        if (e % 7 == 0) body += kMinSlab;                // the one after
        if (e % 13 == 0) body = n + e % 5;               // beyond the grains
        if (body >= n && e % 13 != 0) continue;
        w.push(
            {static_cast<double>(s * 100000 + e) + 0.25 * step, static_cast<std::uint32_t>(body)});
      }
      if (recycle) {
        crossings.apply_to(s, [&](const Entry& x) { got[s].push_back(x.value); });
        crossings.recycle(s);
      }
    }
    if (!recycle)
      for (std::size_t t = 0; t < plan.count; ++t)
        crossings.apply_to(t, [&](const Entry& x) { got[t].push_back(x.value); });
    crossings.apply_to(plan.count, [&](const Entry& x) { got[plan.count].push_back(x.value); });
  }
  return got;
}

TEST(CrossingBlocks, RecycledBucketsGiveEveryEntryInTheSameOrder) {
  for (int steps : {1, 3}) {
    const auto plain = crossings_received(false, steps);
    const auto recycled = crossings_received(true, steps);
    ASSERT_EQ(plain.size(), recycled.size());
    std::size_t total = 0;
    for (std::size_t t = 0; t < plain.size(); ++t) {
      EXPECT_EQ(plain[t], recycled[t]) << "target " << t << " after " << steps << " steps";
      total += plain[t].size();
    }
    EXPECT_GT(total, 1000u);
    EXPECT_TRUE(plain[0].empty());  // nothing reaches the first slab
  }
}

}  // namespace
}  // namespace geodem::test
