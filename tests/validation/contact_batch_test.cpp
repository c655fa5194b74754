// The batched contact loop and its kernels for each instruction set
// (contacts/contact_batch.hpp) give the scalar loop's results to the bit: the same packing run
// on every path the machine supports ends in the same state (positions, velocities, spins,
// springs, wall forces, measured stresses). The cases cover what the kernels branch on: the
// linear law with constant stiffness and a dashpot, with the tangential dashpot, with two
// grain materials (a batch ends where the law changes), Hertz-Mindlin, the linear law from a
// contact modulus (per unit thickness in 2D) with clumps (shared collisions), and a sheared
// periodic cell (image shifts, the affine field's velocity, the cell's sums). The pressed
// packings' box of plane walls (one sliding, with friction) also runs through the two-pass wall
// loop of contacts/plane_walls.cpp on the batch paths, and the grains through the move kernels
// of integrate/move_kernel.hpp, against the scalar loops of the scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <utility>

#include "broadphase/neighbour_search.hpp"
#include "contacts/contact_batch.hpp"
#include "contacts/contact_forces.hpp"
#include "contacts/contact_law.hpp"
#include "moving_worlds.hpp"
#include "pressed_packing.hpp"

namespace geodem::test {
namespace {

template <typename T>
class ContactBatches : public ::testing::Test {};
TYPED_TEST_SUITE(ContactBatches, Dims, DimNames);

enum class Case { kLinear, kTangentialDashpot, kTwoMaterials, kHertz, kClumps, kPeriodic };

const char* case_name(Case c) {
  switch (c) {
    case Case::kLinear:
      return "linear";
    case Case::kTangentialDashpot:
      return "tangential dashpot";
    case Case::kTwoMaterials:
      return "two grain materials";
    case Case::kHertz:
      return "Hertz-Mindlin";
    case Case::kClumps:
      return "clumps, contact modulus";
    case Case::kPeriodic:
      return "sheared periodic cell";
  }
  return "?";
}

template <int D>
World<D> pressed(Case c) {
  World<D> w = pressed_packing<D>(false, 3000, D == 2 ? 50 : 12, 4.0, 3);
  if (c == Case::kTangentialDashpot) w.materials[0].tangential_damping = true;
  if (c == Case::kTwoMaterials) {
    Material rough = w.materials[0];
    rough.name = "rough";
    rough.friction = 0.9;
    const auto m = add_material(w, rough);
    for (std::size_t i = 0; i < w.particles.size(); i += 3) w.particles.material[i] = m;
  }
  if (c == Case::kHertz) {
    for (Material& m : w.materials) {  // the grains and the walls
      m.law = LawKind::kHertz;
      m.young = 2e8;
      m.poisson = 0.3;
    }
  }
  w.resolve_pair_laws();
  w.tally_wall_dashpots = true;  // (what a stress servo reads: compared too)
  return w;
}

// The state after the run, and the most grain-grain contacts measured along it.
template <int D>
std::pair<World<D>, std::size_t> run(Case c, ContactPath path) {
  EXPECT_TRUE(set_contact_path(path));
  World<D> w;
  if (c == Case::kClumps) {
    w = colliding_clumps<D>(D == 2 ? std::array<int, 3>{24, 20, 1} : std::array<int, 3>{7, 7, 7},
                            0.5);
  } else if (c == Case::kPeriodic) {
    w = sheared_cell<D>(D == 2 ? 40 : 12);
  } else {
    w = pressed<D>(c);
  }
#ifdef GEODEM_SANITIZED
  // (under the sanitizers a third of the steps of the pressed packings: every path and branch
  // still runs, on fewer steps; the clumps collide and the cell's contacts form later)
  const int share = c == Case::kClumps || c == Case::kPeriodic ? 1 : 3;
#else
  const int share = 1;
#endif
  const int steps = (c == Case::kClumps ? 1200 : 300) / share;
  std::size_t most = 0;
  for (int k = 0; k < steps; ++k) {
    if (k == 100 / share && !w.walls.empty()) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);
    w.measure_this_step = k % 25 == 0 || k == steps - 1;
    step(w);
    if (w.measure_this_step) most = std::max(most, w.stats.contacts);
  }
  // One step more without measuring (the stresses measured stay): the walls' sums are those of
  // the wall loop that unmeasured steps run.
  w.measure_this_step = false;
  step(w);
  return {std::move(w), most};
}

template <int D>
void expect_identical(const World<D>& a, const World<D>& b) {
  expect_same_grains(a, b);
  EXPECT_TRUE(same_bits(a.particles.force, b.particles.force));
  EXPECT_TRUE(same_bits(a.particles.torque, b.particles.torque));
  for (std::size_t k = 0; k < a.walls.size(); ++k) {
    EXPECT_TRUE(a.walls[k].force == b.walls[k].force) << "wall " << k;
    EXPECT_EQ(a.walls[k].stiffness, b.walls[k].stiffness) << "wall " << k;
    EXPECT_EQ(a.walls[k].dashpot, b.walls[k].dashpot) << "wall " << k;
  }
  EXPECT_TRUE(a.stats.fabric_stress == b.stats.fabric_stress);
  EXPECT_EQ(a.stats.sum_force, b.stats.sum_force);
  EXPECT_EQ(a.stats.contacts, b.stats.contacts);
  EXPECT_EQ(a.stats.elastic_energy, b.stats.elastic_energy);
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_TRUE(same_bits(a.clumps.pos, b.clumps.pos));
  EXPECT_TRUE(same_bits(a.clumps.angvel, b.clumps.angvel));
  EXPECT_TRUE(a.cell.h == b.cell.h);
  EXPECT_TRUE(a.cell_fabric == b.cell_fabric);
  EXPECT_TRUE(a.cell_stiffness == b.cell_stiffness);
}

TYPED_TEST(ContactBatches, EveryPathGivesTheScalarLoopsBits) {
  constexpr int D = TypeParam::value;
  ContactPathGuard guard;
  int compared = 0;
  for (Case c : {Case::kLinear, Case::kTangentialDashpot, Case::kTwoMaterials, Case::kHertz,
                 Case::kClumps, Case::kPeriodic}) {
    SCOPED_TRACE(case_name(c));
    const auto [scalar, most] = run<D>(c, ContactPath::kScalar);
    // The case exercises what it claims: many contacts.
    ASSERT_GT(most, 150u);
    for (ContactPath p : {ContactPath::kBaseline, ContactPath::kAvx2, ContactPath::kAvx512}) {
      if (!contact_path_supported(p)) continue;
      SCOPED_TRACE(contact_path_name(p));
      expect_identical(scalar, run<D>(c, p).first);
      ++compared;
    }
  }
  if (compared == 0) GTEST_SKIP() << "no batch path on this processor";
  report("batch paths compared with the scalar loop (6 cases)", compared / 6);
}

double component(double spin, int) {
  return spin;
}
double component(const Vec<3>& spin, int a) {
  return spin[a];
}

// One kernel call on random contacts, against the scalar law contact by contact: springs
// turned far out of the tangent plane (the kernel's rare branch), sliding and sticking
// contacts, zero springs of either sign, with and without dashpots, both laws.
template <int D>
void expect_kernel_matches_law(const PairLaw& law, ContactPath path, std::mt19937_64& rng) {
  using V = Vec<D>;
  using R = typename Dim<D>::Rot;
  constexpr int n = 61;  // not a multiple of any vector width: the last vector is partial
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<V> pos(2 * n), vel(2 * n);
  std::vector<R> angvel(2 * n);
  std::vector<double> radius(2 * n), inv_mass(2 * n);
  std::vector<TangentSpring<D>> spring(n);
  ContactBatch<D> b{};
  for (int c = 0; c < n; ++c) {
    const std::size_t i = 2 * c, j = 2 * c + 1;
    radius[i] = 1e-3 * (1.0 + 0.5 * u(rng)), radius[j] = 1e-3 * (1.0 + 0.5 * u(rng));
    inv_mass[i] = c % 7 == 0 ? 0.0 : 1e5 * (1.5 + u(rng)), inv_mass[j] = 1e5 * (1.5 + u(rng));
    V dir;
    for (int a = 0; a < D; ++a) dir[a] = u(rng);
    pos[i] = V::Zero();
    pos[j] = dir.normalized() * (radius[i] + radius[j]) * (1.0 - 0.02 * std::abs(u(rng)));
    for (int a = 0; a < D; ++a) vel[i][a] = u(rng), vel[j][a] = u(rng);
    if constexpr (D == 3) {
      for (int a = 0; a < 3; ++a) angvel[i][a] = 100 * u(rng), angvel[j][a] = 100 * u(rng);
      // Springs along random directions: most far from the tangent plane.
      for (int a = 0; a < 3; ++a) spring[c][a] = (c % 5 == 0 ? 1e-3 : 1.0) * u(rng);
      // A third nearly in the tangent plane, as the normal turns little in a step (the
      // series branch).
      const V normal = (pos[j] - pos[i]).normalized();
      if (c % 3 == 1) spring[c] -= (1.0 - 3e-3 * u(rng)) * spring[c].dot(normal) * normal;
      if (c % 11 == 0) spring[c] = V(-0.0, 0.0, -0.0);
    } else {
      angvel[i] = 100 * u(rng), angvel[j] = 100 * u(rng);
      spring[c] = c % 11 == 0 ? -0.0 : u(rng);
    }
    b.i[c] = static_cast<std::int64_t>(i), b.j[c] = static_cast<std::int64_t>(j), b.k[c] = c;
  }
  std::vector<TangentSpring<D>> expected = spring;
  auto doubles = [](auto& v) { return reinterpret_cast<double*>(v.data()); };
  const BatchGrains g{doubles(pos),  doubles(vel),    doubles(angvel),
                      radius.data(), inv_mass.data(), doubles(spring),
                      false};
  const BatchLaw bl{law.law == LawKind::kHertz,
                    law.constant_stiffness,
                    law.per_unit_thickness,
                    law.tangential_damping,
                    law.kn,
                    law.kt,
                    law.e1r,
                    law.e2r,
                    law.kt_over_kn,
                    law.mu,
                    law.beta,
                    law.hertz_damp,
                    law.estar,
                    law.gstar};
  ASSERT_TRUE(set_contact_path(path));
  const double dt = 1e-6;
  batch_contact_forces<D, false>(bl, g, dt, b, n);
  for (int c = 0; c < n; ++c) {
    const std::size_t i = 2 * c, j = 2 * c + 1;
    const V d = pos[j] - pos[i];
    const double dist = std::sqrt(d.squaredNorm());
    const V nrm = d * (1.0 / dist);
    const double delta = radius[i] + radius[j] - dist;
    const double ai = radius[i] - 0.5 * delta, aj = radius[j] - 0.5 * delta;
    const V vrel = (vel[j] - Dim<D>::cross(angvel[j], aj * nrm)) -
                   (vel[i] + Dim<D>::cross(angvel[i], ai * nrm));
    double fn;
    const V f = contact_force<D>(law, radius[i], radius[j], inv_mass[i] + inv_mass[j], nrm, delta,
                                 vrel, dt, expected[c], fn);
    const R tq = Dim<D>::cross(nrm, f);
    V fb;
    for (int a = 0; a < D; ++a) fb[a] = b.f[a][c];
    EXPECT_EQ(std::memcmp(&fb, &f, sizeof(V)), 0) << "contact " << c;
    EXPECT_EQ(std::memcmp(&spring[c], &expected[c], sizeof(spring[c])), 0) << "contact " << c;
    EXPECT_EQ(b.fn[c], fn);
    R ti = ai * tq, tj = -(aj * tq);
    for (int a = 0; a < ContactBatch<D>::kRot; ++a) {
      EXPECT_EQ(b.tqi[a][c], component(ti, a)) << "contact " << c;
      EXPECT_EQ(b.tj[a][c], component(tj, a)) << "contact " << c;
    }
  }
}

TYPED_TEST(ContactBatches, KernelsGiveTheScalarLawsBitsOnRandomContacts) {
  constexpr int D = TypeParam::value;
  ContactPathGuard guard;
  std::mt19937_64 rng(17);
  std::vector<Material> materials;
  materials.push_back(linear_material(1e4, 5e3, 0.4, 0.5));
  materials.push_back(linear_material(1e4, 5e3, 0.4, 0.5));
  materials.back().tangential_damping = true;
  materials.push_back(modulus_material(1e8, 0.4, 0.3, 0.8));
  materials.push_back(hertz_material(1e8, 0.3, 2600.0, 0.5, 0.6));
  materials.push_back(hertz_material(1e8, 0.3, 2600.0, 0.5, 0.6));
  materials.back().tangential_damping = true;
  materials.push_back(linear_material(1e4, 5e3, 0.0, 1.0));  // no friction, no dashpot
  int compared = 0;
  for (ContactPath p : {ContactPath::kBaseline, ContactPath::kAvx2, ContactPath::kAvx512}) {
    if (!contact_path_supported(p)) continue;
    SCOPED_TRACE(contact_path_name(p));
    for (std::size_t m = 0; m < materials.size(); ++m) {
      SCOPED_TRACE(::testing::Message() << "material " << m);
      World<D> w;
      add_material(w, materials[m]);
      w.resolve_pair_laws();
      for (int round = 0; round < 20; ++round) expect_kernel_matches_law<D>(w.pair_laws[0], p, rng);
    }
    ++compared;
  }
  if (compared == 0) GTEST_SKIP() << "no batch path on this processor";
}

// The overlap that stops a run is the first in list order beyond the limit, on every path.
TYPED_TEST(ContactBatches, EveryPathNotesTheSameRunawayOverlap) {
  constexpr int D = TypeParam::value;
  ContactPathGuard guard;
  auto noted = [](ContactPath p) {
    EXPECT_TRUE(set_contact_path(p));
    World<D> w;
    add_material(w, linear_material(1e4, 5e3, 0.5, 0.5));
    w.resolve_pair_laws();
    w.overlap_limit = 0.3;
    // Pairs along x, 3 mm apart: overlaps of 10, 40 and 50 % of the radius (1 mm).
    for (int p2 = 0; p2 < 3; ++p2) {
      const double x = 3e-3 * p2, gap = std::array<double, 3>{1.9e-3, 1.6e-3, 1.5e-3}[p2];
      w.particles.add(vec<D>(x, 0.0, 0.0), 1e-3, 2600.0, 0);
      w.particles.add(vec<D>(x, gap, 0.0), 1e-3, 2600.0, 0);
    }
    w.dt = 1e-6;
    build_neighbour_list(w);
    compute_contact_forces(w);
    return std::array<double, 3>{static_cast<double>(w.overlap_offender),
                                 static_cast<double>(w.overlap_partner), w.overlap_ratio};
  };
  const auto scalar = noted(ContactPath::kScalar);
  EXPECT_GE(scalar[0], 0.0);
  EXPECT_NEAR(scalar[2], 0.4, 1e-12);
  for (ContactPath p : {ContactPath::kBaseline, ContactPath::kAvx2, ContactPath::kAvx512}) {
    if (!contact_path_supported(p)) continue;
    SCOPED_TRACE(contact_path_name(p));
    EXPECT_EQ(noted(p), scalar);
  }
}

TEST(ContactPaths, ScalarAlwaysRunsAndAnUnsupportedPathIsRefused) {
  ContactPathGuard guard;
  EXPECT_TRUE(contact_path_supported(ContactPath::kScalar));
  EXPECT_TRUE(set_contact_path(ContactPath::kScalar));
  EXPECT_EQ(contact_path(), ContactPath::kScalar);
  for (ContactPath p : {ContactPath::kBaseline, ContactPath::kAvx2, ContactPath::kAvx512}) {
    if (contact_path_supported(p)) continue;
    EXPECT_FALSE(set_contact_path(p));
    EXPECT_EQ(contact_path(), ContactPath::kScalar);
  }
  EXPECT_TRUE(contact_path_supported(default_contact_path()));
}

}  // namespace
}  // namespace geodem::test
