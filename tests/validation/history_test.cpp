// Contact history survives neighbour-list rebuilds exactly. A frictional packing settles
// under gravity, then is sheared by its floor sliding sideways; the same run repeated with
// a rebuild before every step, or with another skin, must end in bitwise the same state:
// every pair in contact is listed whatever the list's age, its tangential spring is carried
// over by the merge, and each grain sums its contacts in the same (partner index) order.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class ContactHistory : public ::testing::Test {};
TYPED_TEST_SUITE(ContactHistory, Dims, DimNames);

constexpr double kR0 = 1e-3, kRho = 2600.0;

template <int D>
World<D> make_shear_box() {
  World<D> w;
  const double m0 = kRho * Dim<D>::volume(kR0);
  const double kn = m0 * 9.81 / (1e-3 * kR0);  // overlaps ~ 1e-3 r0 per grain of load
  const auto grain = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 0.5, kRho));
  const auto wall = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 0.5, kRho, "wall"));
  const int per_side = D == 2 ? 16 : 6;
  const double spacing = 2.2 * kR0;
  Vec<D> hi = Vec<D>::Constant(per_side * spacing);
  hi[1] *= 2.0;
  add_box(w, Vec<D>(Vec<D>::Zero()), hi, wall, wall);
  w.resolve_pair_laws();
  std::mt19937_64 rng(7);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), hi, spacing, 0.8 * kR0, kR0, 0.05 * kR0, 0.05, kRho,
               grain, rng, D == 2 ? 300 : 250);
  w.gravity = vec<D>(0.0, -9.81, 0.0);
  w.dt = 0.1 * std::sqrt(kRho * Dim<D>::volume(0.8 * kR0) / kn);
  return w;
}

// Settles for `settle` steps, then slides the floor along x for `shear` steps.
template <int D>
void run_shear(World<D>& w, int settle, int shear, bool rebuild_every_step) {
  for (int k = 0; k < settle + shear; ++k) {
    if (k == settle) w.walls[2].velocity = vec<D>(0.02, 0.0, 0.0);  // wall 2: the floor
    if (rebuild_every_step) w.rebuild_needed = true;
    step(w);
  }
}

template <int D>
void expect_identical(const World<D>& a, const World<D>& b) {
  ASSERT_EQ(a.particles.size(), b.particles.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    const bool same = a.particles.pos[i] == b.particles.pos[i] &&
                      a.particles.vel[i] == b.particles.vel[i] &&
                      a.particles.angvel[i] == b.particles.angvel[i];
    if (!same) ++differ;
  }
  EXPECT_EQ(differ, 0u) << "grains whose state is not bitwise identical";
}

TYPED_TEST(ContactHistory, RebuildsDoNotChangeTheRun) {
  constexpr int D = TypeParam::value;
  const int settle = 6000, shear = 4000;
  World<D> normal = make_shear_box<D>();
  World<D> every = make_shear_box<D>();
  World<D> wide = make_shear_box<D>();
  wide.skin_factor = 1.0;
  run_shear(normal, settle, shear, false);
  run_shear(every, settle, shear, true);
  run_shear(wide, settle, shear, false);
  const int steps = settle + shear;
  report(std::to_string(D) + "D history: list builds / steps (normal run)",
         static_cast<double>(normal.nlist.builds) / steps);
  EXPECT_EQ(every.nlist.builds, static_cast<std::uint64_t>(steps));
  EXPECT_LT(normal.nlist.builds, static_cast<std::uint64_t>(steps / 5));
  EXPECT_LT(wide.nlist.builds, normal.nlist.builds);

  // The test means something only if friction is at work: many loaded tangential springs.
  std::size_t loaded = 0, contacts = 0;
  const auto& P = normal.particles;
  const auto& L = normal.nlist;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::uint32_t j = L.other[k];
      if ((P.pos[j] - P.pos[i]).norm() >= P.radius[i] + P.radius[j]) continue;
      ++contacts;
      if (L.spring[k].norm() > 0.0) ++loaded;
    }
  EXPECT_GT(contacts, P.size());
  EXPECT_GT(loaded, contacts / 2);
  // The shear moved the grains: the floor drags the packing.
  double mean_vx = 0.0;
  for (std::size_t i = 0; i < P.size(); ++i)
    mean_vx += P.vel[i].x() / static_cast<double>(P.size());
  EXPECT_GT(std::abs(mean_vx), 1e-4);

  expect_identical(normal, every);
  expect_identical(normal, wide);
}

}  // namespace
}  // namespace geodem::test
