// Contact cohesion (contacts/bonds.hpp, bonded_contact_force in contacts/contact_law.hpp).
// Two bonded grains are pulled apart (or sheared) slowly by moving one at a constant
// velocity, the other held: the contact force grows linearly until the bond breaks at
// its strength (within 1 %: the last increment is k v dt, about 1e-4 of the strength),
// then the grains are free. Strengths given as forces and as stresses scaled by the
// contact size (pi r_min^2 in 3D, 2 r_min per metre in 2D).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "contacts/bonds.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class Bond : public ::testing::Test {};
TYPED_TEST_SUITE(Bond, Dims, DimNames);

constexpr double kR = 0.01, kKn = 1e5;

struct PullResult {
  double peak;           // largest bond force along the pull (N, or N/m in 2D)
  double after;          // force at the end, once broken
  std::uint64_t broken;  // bonds broken
  std::size_t created;
};

// Grain 1 (radius 0.8 kR) moves along `dir` from touching grain 0, at a speed that
// reaches the expected strength in 10,000 steps.
template <int D>
PullResult pull(const Material& m, const Vec<D>& dir, double strength) {
  World<D> w;
  const auto mat = add_material(w, m);
  w.resolve_pair_laws();
  const double r1 = 0.8 * kR;
  w.particles.add(Vec<D>::Zero(), kR, 2600.0, mat, Vec<D>::Zero(), Dim<D>::zero_rot(), true);
  const double dt = 1e-6, v = strength / (0.5 * kKn) / (1e4 * dt);
  w.particles.add(Vec<D>((kR + r1) * axis<D>(0)), r1, 2600.0, mat, Vec<D>(v * dir),
                  Dim<D>::zero_rot(), true);
  w.dt = dt;
  PullResult res{};
  res.created = create_bonds(w);
  for (int k = 0; k < 40000; ++k) {
    step(w);
    res.peak = std::max(res.peak, std::abs(w.particles.force[1].dot(dir)));
  }
  res.after = w.particles.force[1].norm();
  res.broken = w.broken_bonds;
  EXPECT_EQ(intact_bonds(w), 0u);
  return res;
}

TYPED_TEST(Bond, BreaksInTensionAtItsStrength) {
  constexpr int D = TypeParam::value;
  Material m = linear_material(kKn, 0.5 * kKn, 0.5, 1.0);
  m.cohesion_as_force = true;
  m.normal_cohesion = 1.0;  // N (N/m in 2D)
  m.shear_cohesion = 10.0;
  const PullResult r = pull<D>(m, axis<D>(0), 1.0);
  report(std::to_string(D) + "D bond tensile strength (force)", rel_err(r.peak, 1.0));
  EXPECT_EQ(r.created, 1u);
  EXPECT_LT(rel_err(r.peak, 1.0), 0.01);
  EXPECT_EQ(r.broken, 1u);
  EXPECT_EQ(r.after, 0.0);
}

TYPED_TEST(Bond, StressStrengthScalesWithContactSize) {
  constexpr int D = TypeParam::value;
  Material m = linear_material(kKn, 0.5 * kKn, 0.5, 1.0);
  m.normal_cohesion = 2e3;  // Pa
  m.shear_cohesion = 2e4;
  const double rmin = 0.8 * kR;
  const double want = 2e3 * (D == 2 ? 2.0 * rmin : std::numbers::pi * rmin * rmin);
  const PullResult r = pull<D>(m, axis<D>(0), want);
  report(std::to_string(D) + "D bond tensile strength (stress)", rel_err(r.peak, want));
  EXPECT_LT(rel_err(r.peak, want), 0.01);
  EXPECT_EQ(r.broken, 1u);
}

TYPED_TEST(Bond, BreaksInShearAtItsStrength) {
  constexpr int D = TypeParam::value;
  Material m = linear_material(kKn, 0.5 * kKn, 0.5, 1.0);
  m.cohesion_as_force = true;
  m.normal_cohesion = 10.0;
  m.shear_cohesion = 1.0;
  const PullResult r = pull<D>(m, axis<D>(1), 1.0);
  report(std::to_string(D) + "D bond shear strength (force)", rel_err(r.peak, 1.0));
  EXPECT_LT(rel_err(r.peak, 1.0), 0.01);
  EXPECT_EQ(r.broken, 1u);
  EXPECT_EQ(r.after, 0.0);  // sheared off, the grains no longer touch
}

// Without a bond the same pull gives no tension at all.
TYPED_TEST(Bond, UnbondedGrainsDoNotPull) {
  constexpr int D = TypeParam::value;
  Material m = linear_material(kKn, 0.5 * kKn, 0.5, 1.0);
  World<D> w;
  const auto mat = add_material(w, m);
  w.resolve_pair_laws();
  EXPECT_FALSE(w.contact_extras);
  w.particles.add(Vec<D>::Zero(), kR, 2600.0, mat, Vec<D>::Zero(), Dim<D>::zero_rot(), true);
  w.particles.add(Vec<D>(1.8 * kR * axis<D>(0)), 0.8 * kR, 2600.0, mat, Vec<D>(1e-3 * axis<D>(0)),
                  Dim<D>::zero_rot(), true);
  w.dt = 1e-6;
  EXPECT_EQ(create_bonds(w), 0u);
  for (int k = 0; k < 100; ++k) step(w);
  EXPECT_EQ(w.particles.force[1].norm(), 0.0);
}

}  // namespace
}  // namespace geodem::test
