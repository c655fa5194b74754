// Contact history survives neighbour-list rebuilds exactly. A frictional packing settles
// under gravity, then is sheared by its floor sliding sideways; the same run repeated with
// a rebuild before every step, or with another skin, must end in bitwise the same state:
// every pair in contact is listed whatever the list's age, its tangential spring is carried
// over by the merge, and each grain sums its contacts in the same (partner index) order.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include <map>
#include <utility>

#include "broadphase/neighbour_search.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class ContactHistory : public ::testing::Test {};
TYPED_TEST_SUITE(ContactHistory, Dims, DimNames);

constexpr double kR0 = 1e-3, kRho = 2600.0;

// `eta`: rolling and twisting friction of grains and walls (0: none).
template <int D>
World<D> make_shear_box(double eta = 0.0) {
  World<D> w;
  const double m0 = kRho * Dim<D>::volume(kR0);
  const double kn = m0 * 9.81 / (1e-3 * kR0);  // overlaps ~ 1e-3 r0 per grain of load
  Material gm = linear_material(kn, 0.5 * kn, 0.5, 0.5, kRho);
  Material wm = linear_material(kn, 0.5 * kn, 0.5, 0.5, kRho, "wall");
  gm.rolling_friction = gm.twisting_friction = wm.rolling_friction = wm.twisting_friction = eta;
  const auto grain = add_material(w, gm);
  const auto wall = add_material(w, wm);
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
      if (spring_norm2<D>(L.spring[k]) > 0.0) ++loaded;
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

// Tangential springs of the listed pairs keyed by grain ids, each expressed as the
// force on the grain with the larger id.
template <int D>
std::map<std::pair<std::uint32_t, std::uint32_t>, TangentSpring<D>> springs_by_id(
    const World<D>& w) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, TangentSpring<D>> out;
  const auto& P = w.particles;
  const auto& L = w.nlist;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::uint32_t a = P.id[i], b = P.id[L.other[k]];
      // The row's spring is the force on grain `other` (b).
      if (a < b)
        out[{a, b}] = L.spring[k];
      else
        out[{b, a}] = spring_from_other_body<D>(L.spring[k]);
    }
  return out;
}

// Steps a reference run and its renumbered copy once, then returns the largest difference
// of a per-grain quantity (matched by grain id) over its largest value in the reference.
template <int D, typename Get>
double step_and_compare(World<D>& reference, World<D>& renumbered, Get get) {
  reference.rebuild_needed = true;
  step(reference);
  step(renumbered);
  std::vector<std::size_t> where(renumbered.particles.size());
  for (std::size_t i = 0; i < renumbered.particles.size(); ++i)
    where[renumbered.particles.id[i]] = i;
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < reference.particles.size(); ++i) {
    const std::size_t j = where[reference.particles.id[i]];
    worst = std::max(worst, (get(reference, i) - get(renumbered, j)).norm());
    scale = std::max(scale, get(reference, i).norm());
  }
  return worst / scale;
}

// Renumbering grains in cell order (done at list builds) carries every spring over to
// the pair's new row exactly, with the sign flipped when the pair's order swaps; one step
// after it, the forces on each grain agree with an unrenumbered run to rounding.
TYPED_TEST(ContactHistory, RenumberingKeepsEverySpring) {
  constexpr int D = TypeParam::value;
  World<D> w = make_shear_box<D>();
  run_shear(w, 3000, 1000, false);
  World<D> reference = make_shear_box<D>();  // the same run, deterministic
  run_shear(reference, 3000, 1000, false);
  const auto before = springs_by_id(w);
  std::size_t loaded = 0;
  for (const auto& [key, s] : before) loaded += spring_norm2<D>(s) > 0.0;
  ASSERT_GT(loaded, w.particles.size() / 2) << "the test needs loaded springs";

  w.sort_interval = 1;
  build_neighbour_list(w);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < w.particles.size(); ++i) moved += w.particles.id[i] != i;
  ASSERT_GT(moved, w.particles.size() / 2) << "the grains were not renumbered";

  const auto after = springs_by_id(w);
  std::size_t checked = 0;
  for (const auto& [key, s] : before) {
    if (spring_norm2<D>(s) == 0.0) continue;  // pairs apart may leave the list; loaded ones may not
    const auto it = after.find(key);
    ASSERT_NE(it, after.end()) << "a loaded pair was lost";
    EXPECT_TRUE(it->second == s) << "spring of pair " << key.first << "-" << key.second;
    ++checked;
  }
  EXPECT_EQ(checked, loaded);

  const double err = step_and_compare(
      reference, w, [](const World<D>& x, std::size_t i) { return Vec<D>(x.particles.force[i]); });
  report(std::to_string(D) + "D renumbering: largest force difference / largest force", err);
  EXPECT_LT(err, 1e-12);
}

// The same with rolling and twisting springs: renumbering carries them over (the rolling
// moment reversed, the twist value kept, when the pair's order swaps), so the torques one
// step later agree with an unrenumbered run.
TYPED_TEST(ContactHistory, RenumberingKeepsRollingAndTwistingSprings) {
  constexpr int D = TypeParam::value;
  World<D> w = make_shear_box<D>(0.3);
  run_shear(w, 3000, 1000, false);
  World<D> reference = make_shear_box<D>(0.3);
  run_shear(reference, 3000, 1000, false);
  std::size_t loaded = 0;
  for (const auto& e : w.nlist.extra)
    loaded += Dim<D>::rot_norm2(e.roll) > 0.0 && (D == 2 || e.twist != 0.0);
  ASSERT_GT(loaded, w.particles.size() / 4) << "the test needs loaded moment springs";
  w.sort_interval = 1;
  build_neighbour_list(w);
  const double err = step_and_compare(reference, w, [](const World<D>& x, std::size_t i) {
    return Eigen::Matrix<double, Dim<D>::rot_dofs, 1>(x.particles.torque[i]);
  });
  report(std::to_string(D) + "D renumbering with moment springs: torque difference / largest", err);
  EXPECT_LT(err, 1e-12);
}

// Grain-spar element springs (a sheet on the floor of the shear box, dragged with it) are
// carried over by renumbering too: one step later, the forces on grains and nodes agree.
TYPED_TEST(ContactHistory, RenumberingKeepsSparContactSprings) {
  constexpr int D = TypeParam::value;
  auto make = [] {
    World<D> w = make_shear_box<D>();
    const double width = w.walls[1].point[0];  // wall 1: the x_hi wall
    // 2D: one sheet; 3D: parallel cables across the floor.
    const int lines = D == 2 ? 1 : 6;
    for (int c = 0; c < lines; ++c) {
      std::vector<Vec<D>> pts;
      for (int k = 0; k <= 12; ++k)
        pts.push_back(vec<D>(width * k / 12.0, 0.0, width * (c + 0.5) / lines));
      w.spars.add_chain("sheet" + std::to_string(c), pts, 1e3, 1e-3, 0.4 * kR0, 1);
    }
    for (std::size_t i = 0; i < w.spars.nodes(); ++i) w.spars.flags[i] = kNodeDriven;
    return w;
  };
  auto run = [](World<D>& w) {
    run_shear(w, 3000, 0, false);
    for (auto& v : w.spars.vel) v = vec<D>(0.02, 0.0, 0.0);  // dragged with the floor
    run_shear(w, 0, 1000, false);
  };
  World<D> w = make(), reference = make();
  run(w);
  run(reference);
  std::size_t loaded = 0;
  for (const auto& s : w.nlist.spar_spring) loaded += spring_norm2<D>(s) > 0.0;
  report(std::to_string(D) + "D renumbering with a sheet: loaded grain-sheet springs",
         static_cast<double>(loaded));
  ASSERT_GT(loaded, 3u) << "the test needs loaded grain-sheet springs";
  w.sort_interval = 1;
  build_neighbour_list(w);
  const double err = step_and_compare(
      reference, w, [](const World<D>& x, std::size_t i) { return Vec<D>(x.particles.force[i]); });
  double node_err = 0.0, node_scale = 0.0;
  for (std::size_t i = 0; i < w.spars.nodes(); ++i) {
    node_err = std::max(node_err, (w.spars.force[i] - reference.spars.force[i]).norm());
    node_scale = std::max(node_scale, reference.spars.force[i].norm());
  }
  report(std::to_string(D) + "D renumbering with a sheet: grain force difference / largest", err);
  report(std::to_string(D) + "D renumbering with a sheet: node force difference / largest",
         node_err / node_scale);
  EXPECT_LT(err, 1e-12);
  EXPECT_LT(node_err / node_scale, 1e-12);
}

}  // namespace
}  // namespace geodem::test
