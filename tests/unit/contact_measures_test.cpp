// Pair-law mixing rules, the Love-Weber average stress of a known static chain of forces,
// the fabric tensor of lattices, and the automatic time step.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "base/error.hpp"
#include "broadphase/neighbour_search.hpp"
#include "clumps/clump_dynamics.hpp"
#include "integrate/critical_timestep.hpp"
#include "measure/contact_network.hpp"
#include "measure/measurements.hpp"
#include "test_util.hpp"
#include "world/step.hpp"

namespace geodem::test {
namespace {

TEST(PairLaw, DampingRatioGivesRestitution) {
  EXPECT_EQ(damping_ratio(1.0), 0.0);
  for (double e : {0.05, 0.3, 0.8, 0.99}) {
    const double b = damping_ratio(e);
    // Restitution of the linear spring-dashpot: exp(-pi beta / sqrt(1 - beta^2)).
    EXPECT_NEAR(std::exp(-std::numbers::pi * b / std::sqrt(1.0 - b * b)), e, 1e-14);
  }
}

TEST(PairLaw, LinearMixingRules) {
  const Material a = linear_material(2e5, 1e5, 0.6, 0.9);
  const Material b = linear_material(6e5, 2e5, 0.3, 0.4);
  const PairLaw p = combine(a, b);
  EXPECT_TRUE(p.constant_stiffness);
  EXPECT_NEAR(p.kn, 2e5 * 6e5 / 8e5, 1e-9);  // springs in series
  EXPECT_NEAR(p.kt, 1e5 * 2e5 / 3e5, 1e-9);
  EXPECT_EQ(p.mu, 0.3);                   // smaller friction
  EXPECT_EQ(p.beta, damping_ratio(0.4));  // smaller restitution
  const PairLaw same = combine(a, a);
  EXPECT_EQ(same.kn, 2e5);
  EXPECT_EQ(same.kt, 1e5);
  // Modulus form: kn = 2 E r1 r2 / (r1 + r2) for equal moduli.
  const Material m = modulus_material(1e8, 0.25, 0.5, 1.0);
  const PairLaw pm = combine(m, m);
  EXPECT_NEAR(pm.linear_kn(0.01, 0.03), 2e8 * 0.01 * 0.03 / 0.04, 1e-6);
  EXPECT_NEAR(pm.linear_kt(pm.linear_kn(0.01, 0.03)), 0.25 * 2e8 * 0.01 * 0.03 / 0.04, 1e-6);
}

TEST(PairLaw, HertzEffectiveModuli) {
  const Material a = hertz_material(7e10, 0.33, 2700.0);
  const Material b = hertz_material(2e11, 0.29, 7800.0);
  const PairLaw p = combine(a, b);
  const double estar = 1.0 / ((1 - 0.33 * 0.33) / 7e10 + (1 - 0.29 * 0.29) / 2e11);
  const double gstar =
      1.0 / (2 * (2 - 0.33) * (1 + 0.33) / 7e10 + 2 * (2 - 0.29) * (1 + 0.29) / 2e11);
  EXPECT_LT(rel_err(p.estar, estar), 1e-14);
  EXPECT_LT(rel_err(p.gstar, gstar), 1e-14);
  EXPECT_THROW(combine(a, linear_material(1e5, 1e5, 0.5, 1.0)), std::invalid_argument);
}

template <typename T>
class AverageStress : public ::testing::Test {};
TYPED_TEST_SUITE(AverageStress, Dims, DimNames);

// Two grains stacked between a floor (y = 0) and a ceiling, all three contacts carrying the
// same force F: a static chain. Love-Weber: sigma V = sum of branch (x) force; the branch to
// a wall ends on the wall's surface (a rigid wall does not indent), so sigma_yy V = F H with H
// the wall spacing (the distance between the two wall contact points), the boundary's own
// measure of the stress; every other component vanishes.
TYPED_TEST(AverageStress, TwoGrainsPressedBetweenWalls) {
  constexpr int D = TypeParam::value;
  const double kn = 2e5, r = 0.01, force = 30.0, volume = 2.5e-4;
  World<D> w;
  const auto mat = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 1.0));
  const double dw = force / kn, dg = force / kn;  // same kn grain-grain and grain-wall
  const double y1 = r - dw, y2 = y1 + 2.0 * r - dg, top = y2 + r - dw;
  add_plane(w, vec<D>(0.0, 0.0), vec<D>(0.0, 1.0), mat, "floor");
  add_plane(w, vec<D>(0.0, top), vec<D>(0.0, -1.0), mat, "ceiling");
  w.resolve_pair_laws();
  w.particles.add(vec<D>(0.3, y1, -0.2), r, 2600.0, mat);
  w.particles.add(vec<D>(0.3, y2, -0.2), r, 2600.0, mat);
  w.dt = 1e-6;
  w.measure_this_step = true;
  step(w);

  EXPECT_EQ(w.stats.contacts, 1u);
  EXPECT_EQ(w.stats.wall_contacts, 2u);
  EXPECT_NEAR(w.stats.sum_force, 3.0 * force, 1e-9 * force);
  EXPECT_NEAR(w.stats.elastic_energy, 3.0 * 0.5 * force * force / kn, 1e-9 * force * dw);
  EXPECT_NEAR(coordination_number(w), 1.0, 1e-15);
  // Balanced: the chain is in equilibrium.
  EXPECT_LT(unbalanced_force_ratio(w), 1e-9);
  EXPECT_NEAR(-w.walls[0].force.dot(w.walls[0].normal), force, 1e-9 * force);
  EXPECT_NEAR(-w.walls[1].force.dot(w.walls[1].normal), force, 1e-9 * force);

  const auto sigma = average_stress(w, volume);
  const double want = force * top / volume;  // top = 4 r - dg - 2 dw
  EXPECT_LT(rel_err(sigma(1, 1), want), 1e-12);
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      if (a != 1 || b != 1) {
        EXPECT_NEAR(sigma(a, b), 0.0, 1e-12 * want) << a << b;
      }
}

// The same chain laid along x and rotated: the stress tensor rotates with it.
TYPED_TEST(AverageStress, RotatedChainGivesRotatedTensor) {
  constexpr int D = TypeParam::value;
  const double kn = 2e5, r = 0.01, force = 10.0, volume = 1e-3, angle = 0.3;
  World<D> w;
  const auto mat = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 1.0));
  const Vec<D> n = vec<D>(std::cos(angle), std::sin(angle));
  const double d = force / kn;
  const double s1 = r - d, s2 = s1 + 2.0 * r - d, top = s2 + r - d;
  add_plane(w, Vec<D>::Zero(), n, mat, "a");
  add_plane(w, Vec<D>(top * n), Vec<D>(-n), mat, "b");
  w.resolve_pair_laws();
  w.particles.add(Vec<D>(s1 * n), r, 2600.0, mat);
  w.particles.add(Vec<D>(s2 * n), r, 2600.0, mat);
  w.dt = 1e-6;
  w.measure_this_step = true;
  step(w);
  const auto sigma = average_stress(w, volume);
  const auto want = (force * top / volume * n * n.transpose()).eval();
  EXPECT_LT((sigma - want).norm(), 1e-10 * want.norm());
}

// The same two grains as one clump (overlapping members, so that the branch vectors differ
// from a chain's): the Love-Weber sum over bodies takes the clump's centre, and its two wall
// contacts (on the walls' surfaces) give sigma_yy V = F (distance between the contact points)
// = F H, H = d + 2 r - 2 dw the wall spacing. Without the clump correction the sum would miss
// F d.
TYPED_TEST(AverageStress, ClumpPressedBetweenWalls) {
  constexpr int D = TypeParam::value;
  const double kn = 2e5, r = 0.01, d = 1.5 * r, force = 30.0, volume = 2.5e-4;
  World<D> w;
  const auto mat = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 1.0));
  const double dw = force / kn;
  const double centre = r - dw + 0.5 * d, top = d + 2.0 * r - 2.0 * dw;
  add_plane(w, vec<D>(0.0, 0.0), vec<D>(0.0, 1.0), mat, "floor");
  add_plane(w, vec<D>(0.0, top), vec<D>(0.0, -1.0), mat, "ceiling");
  w.resolve_pair_laws();
  ClumpTemplate<D> t;
  t.centre = {Vec<D>::Zero(), Vec<D>(d * axis<D>(1))};
  t.radius = {r, r};
  // 2D templates keep their frame; in 3D the body frame is the principal one, whose first
  // axis (smallest moment) is the long axis: turn it onto y.
  typename Dim<D>::Orient q;
  if constexpr (D == 2)
    q = 0.0;
  else
    q = Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec<3>(0, 0, 1)));
  const auto c = resolve_clump(t);
  add_clump(w, c, vec<D>(0.3, centre, -0.2), q, 1.0, 2600.0, mat);
  ASSERT_NEAR(w.particles.pos[0][1] + w.particles.pos[1][1], 2.0 * centre, 1e-12);
  ASSERT_NEAR(std::abs(w.particles.pos[0][1] - w.particles.pos[1][1]), d, 1e-12);
  w.dt = 1e-9;
  w.measure_this_step = true;
  step(w);
  EXPECT_EQ(w.stats.contacts, 0u);  // members of one clump are never paired
  EXPECT_EQ(w.stats.wall_contacts, 2u);
  EXPECT_LT(unbalanced_force_ratio(w), 1e-9);
  const auto sigma = average_stress(w, volume);
  const double want = force * top / volume;
  EXPECT_LT(rel_err(sigma(1, 1), want), 1e-9);
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      if (a != 1 || b != 1) {
        EXPECT_NEAR(sigma(a, b), 0.0, 1e-9 * want) << a << b;
      }
}

template <typename T>
class CriticalTimestep : public ::testing::Test {};
TYPED_TEST_SUITE(CriticalTimestep, Dims, DimNames);

// The rule of yade's GlobalStiffnessTimeStepper in closed form: a lone grain counts as
// meeting an equal grain, dt = safety sqrt(2 m / kn); the inner grain of a square (cubic)
// lattice has a diagonal stiffness 2 kn + (2D - 2) kt along each axis and 4 kt r^2 about
// each axis, and the smallest of m/K_t, I/K_r sets the step.
TYPED_TEST(CriticalTimestep, MatchesTheDiagonalStiffnessRule) {
  constexpr int D = TypeParam::value;
  const double kn = 1e5, kt = 0.5 * kn, r = 0.01, rho = 2600.0, safety = 0.8;
  World<D> w;
  const auto mat = add_material(w, linear_material(kn, kt, 0.5, 1.0, rho));
  w.resolve_pair_laws();
  w.particles.add(Vec<D>::Zero(), r, rho, mat);
  build_neighbour_list(w);
  const double m = mass(w, 0), inertia = Dim<D>::inertia_factor() * m * r * r;
  EXPECT_NEAR(critical_timestep(w), safety * std::sqrt(2.0 * m / kn), 1e-12);

  World<D> packed;
  add_material(packed, linear_material(kn, kt, 0.5, 1.0, rho));
  packed.resolve_pair_laws();
  std::mt19937_64 rng(1);
  fill_lattice(packed, Vec<D>(Vec<D>::Zero()), Vec<D>(Vec<D>::Constant(6 * 1.9 * r)), 1.9 * r, r, r,
               0.0, 0.0, rho, 0, rng);
  build_neighbour_list(packed);
  const double k_trans = 2.0 * kn + (2 * D - 2) * kt, k_rot = 4.0 * kt * r * r;
  const double want = safety * std::sqrt(2.0 * std::min(m / k_trans, inertia / k_rot));
  EXPECT_NEAR(critical_timestep(packed), want, 1e-12 * want);
}

// The automatic step keeps an undamped, frictional (no sliding) lattice stable: its
// energy, kinetic plus the elastic energy of the normal springs, stays within a few
// per cent of the start over 20,000 steps (an unstable step grows it exponentially).
TYPED_TEST(CriticalTimestep, AutomaticStepKeepsAnUndampedLatticeStable) {
  constexpr int D = TypeParam::value;
  const double kn = 1e5, r = 0.01, rho = 2600.0;
  auto make = [&]() {
    World<D> w;
    add_material(w, linear_material(kn, 0.5 * kn, 100.0, 1.0, rho));
    w.resolve_pair_laws();
    std::mt19937_64 rng(3);
    fill_lattice(w, Vec<D>(Vec<D>::Zero()), Vec<D>(Vec<D>::Constant(6 * 1.9 * r)), 1.9 * r, r, r,
                 0.0, 0.01, rho, 0, rng);
    w.auto_dt = true;
    return w;
  };
  auto energy = [](World<D>& w) {
    w.measure_this_step = true;
    step(w);
    return kinetic_energy(w) + w.stats.elastic_energy;
  };
  World<D> w = make();
  const double e0 = energy(w);
  double worst = 0.0;
  for (int k = 0; k < 20000; ++k) {
    w.measure_this_step = false;
    step(w);
    if (k % 1000 == 0) worst = std::max(worst, energy(w) / e0);
  }
  report(std::to_string(D) + "D largest energy / initial energy at the automatic step", worst);
  EXPECT_LT(worst, 1.05);
}

// Contact dashpots lower the explicit step's stability limit from omega dt = 2 to
// 2 (sqrt(1 + z^2) - z), z the damping ratio (0.53 of it at e = 0.05, z = 0.69): the step
// takes that factor (closed form for a lone grain). Two grains pressed between two walls
// (equal overlaps, in equilibrium), set oscillating in antiphase (omega^2 = 3 kn/m): at the
// automatic step the oscillation dies out; at the step of the undamped rule it grows.
TYPED_TEST(CriticalTimestep, DashpotsLowerTheStep) {
  constexpr int D = TypeParam::value;
  const double kn = 1e5, r = 0.01, rho = 2600.0, e = 0.05, d = 1e-3 * r, v0 = 1e-6;
  const double z = damping_ratio(e), factor = std::sqrt(1.0 + z * z) - z;
  auto make = [&]() {
    World<D> w;
    const auto mat = add_material(w, linear_material(kn, 0.5 * kn, 0.5, e, rho));
    const double x1 = r - d, x2 = x1 + 2.0 * r - d;
    add_plane(w, Vec<D>::Zero(), axis<D>(0), mat, "left");
    add_plane(w, Vec<D>((x2 + r - d) * axis<D>(0)), Vec<D>(-axis<D>(0)), mat, "right");
    w.resolve_pair_laws();
    w.particles.add(Vec<D>(x1 * axis<D>(0)), r, rho, mat, Vec<D>(v0 * axis<D>(0)));
    w.particles.add(Vec<D>(x2 * axis<D>(0)), r, rho, mat, Vec<D>(-v0 * axis<D>(0)));
    build_neighbour_list(w);
    return w;
  };
  World<D> lone;
  add_material(lone, linear_material(kn, 0.5 * kn, 0.5, e, rho));
  lone.resolve_pair_laws();
  lone.particles.add(Vec<D>::Zero(), r, rho, 0);
  build_neighbour_list(lone);
  const double m = mass(lone, 0);
  EXPECT_NEAR(critical_timestep(lone), 0.8 * factor * std::sqrt(2.0 * m / kn),
              1e-12 * std::sqrt(m / kn));
  auto largest_speed = [&](World<D>& w, double dt, int steps) {
    w.dt = dt;
    double v = 0.0;
    for (int k = 0; k < steps; ++k) {
      step(w);
      v = std::max({v, w.particles.vel[0].norm(), w.particles.vel[1].norm()});
    }
    return v;
  };
  World<D> a = make();
  const double dt = critical_timestep(a);
  largest_speed(a, dt, 200);
  const double late = largest_speed(a, dt, 20);
  World<D> b = make();
  const double grown = largest_speed(b, dt / factor, 30);
  report(std::to_string(D) + "D damped pair at the automatic step: speed after 200 steps / v0",
         late / v0);
  report(std::to_string(D) + "D damped pair at the undamped rule's step: largest speed / v0",
         grown / v0);
  EXPECT_LT(late, 1e-6 * v0);
  EXPECT_GT(grown, 10.0 * v0);
}

TEST(CriticalTimestep, HertzBelowTheContactPeriod) {
  const double r = 0.01, rho = 2800.0, young = 4.8e10, nu = 0.2;
  World<3> w;
  add_material(w, hertz_material(young, nu, rho));
  w.resolve_pair_laws();
  const double delta = 1e-3 * r;
  w.particles.add(vec<3>(0.0, 0.0), r, rho, 0);
  w.particles.add(vec<3>(2.0 * r - delta, 0.0), r, rho, 0);
  build_neighbour_list(w);
  const double dt = critical_timestep(w);
  const double estar = young / (2.0 * (1.0 - nu * nu));
  const double k = 2.0 * estar * std::sqrt(0.5 * r * delta);  // dF/d(delta) at this overlap
  EXPECT_GT(dt, 0.0);
  EXPECT_LT(dt, std::sqrt(mass(w, 0) / k));
}

// The Hertz law's stored energy, 2/5 fn delta: two equal spheres meeting head on at v0 each,
// undamped and frictionless, keep kinetic plus elastic energy through the collision; at the
// deepest overlap the whole 1/2 m* (2 v0)^2 is elastic, and that overlap is Hertz's
// delta_max = (15 m* (2 v0)^2 / (16 E* sqrt(R*)))^(2/5).
TEST(ContactEnergy, HertzCollisionKeepsItsEnergy) {
  const double r = 0.01, rho = 2800.0, young = 1e8, nu = 0.3, v0 = 0.5;
  World<3> w;
  add_material(w, hertz_material(young, nu, rho));
  w.resolve_pair_laws();
  w.particles.add(vec<3>(0.0, 0.0), r, rho, 0, vec<3>(v0, 0.0));
  w.particles.add(vec<3>(2.0 * r + 1e-5, 0.0), r, rho, 0, vec<3>(-v0, 0.0));
  w.auto_dt = false;
  w.dt = 5e-8;  // the contact lasts about 8.5e-4 s
  const double mstar = 0.5 * mass(w, 0), e0 = kinetic_energy(w);
  const double estar = young / (2.0 * (1.0 - nu * nu));
  const double delta_max =
      std::pow(15.0 * mstar * 4.0 * v0 * v0 / (16.0 * estar * std::sqrt(0.5 * r)), 0.4);
  double deepest = 0.0, stored = 0.0, worst = 0.0;
  for (int k = 0; k < 20000; ++k) {
    w.measure_this_step = true;
    step(w);
    const double delta = 2.0 * r - (w.particles.pos[1] - w.particles.pos[0]).norm();
    const double e = kinetic_energy(w) + w.stats.elastic_energy;
    worst = std::max(worst, std::abs(e - e0) / e0);
    if (delta > deepest) deepest = delta, stored = w.stats.elastic_energy;
  }
  report("Hertz collision: largest |E - E0| / E0", worst);
  report("Hertz collision: deepest overlap / delta_max - 1", deepest / delta_max - 1.0);
  report("Hertz collision: elastic energy there / E0 - 1", stored / e0 - 1.0);
  EXPECT_LT(worst, 1e-3);  // leapfrog: velocities half a step from positions
  EXPECT_NEAR(deepest, delta_max, 1e-3 * delta_max);
  EXPECT_NEAR(stored, e0, 1e-3 * e0);
  EXPECT_GT(w.particles.vel[1][0], 0.0);  // bounced apart
}

// Fabric of lattices in closed form. A hexagonal disc patch: n_h horizontal contacts and n_d at
// +-60 degrees give F_xx = (n_h + n_d / 4) / N, F_yy = 3 n_d / 4 / N (isotropic only in an
// infinite lattice: the patch's edges lack diagonal contacts). A cubic sphere patch has
// F = I / 3 exactly; a single row of grains, F = e1 (x) e1 and anisotropy D (the largest
// for a unit trace). The contact network lists every touching pair
// once, with the lattice's overlap and the linear law's force kn delta.
TEST(Fabric, LatticesInClosedForm) {
  const double r = 1.0, delta = 1e-3, d = 2.0 * r - delta;
  {
    World<2> w;
    const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 0.5));
    w.resolve_pair_laws();
    for (int row = 0; row < 9; ++row)
      for (int col = 0; col < 9; ++col)
        w.particles.add(vec<2>(d * (col + 0.5 * (row % 2)), d * std::sqrt(3.0) / 2.0 * row), r,
                        1000.0, mat);
    build_neighbour_list(w);
    // 9 rows of 8 horizontal pairs, and 8 gaps between rows of 17 diagonal pairs each.
    const double nh = 9 * 8, nd = 8 * 17, n = nh + nd;
    const auto f = fabric_tensor(w);
    EXPECT_NEAR(f(0, 0), (nh + nd / 4.0) / n, 1e-12);
    EXPECT_NEAR(f(1, 1), 0.75 * nd / n, 1e-12);
    EXPECT_NEAR(f(0, 1), 0.0, 1e-12);
    EXPECT_NEAR(fabric_anisotropy<2>(f), 2.0 * (f(0, 0) - f(1, 1)), 1e-12);
    const auto c = contact_network(w);
    EXPECT_EQ(c.size(), static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < c.size(); ++k) {
      EXPECT_LT(c.i[k], c.j[k]);
      EXPECT_NEAR(c.overlap[k], delta, 1e-12);
      EXPECT_NEAR(c.normal_force[k], 1e5 * delta, 1e-6);
      EXPECT_NEAR(c.normal[k].norm(), 1.0, 1e-14);
    }
  }
  {
    World<3> w;
    const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 0.5));
    w.resolve_pair_laws();
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b)
        for (int c = 0; c < 5; ++c) w.particles.add(vec<3>(d * a, d * b, d * c), r, 1000.0, mat);
    build_neighbour_list(w);
    const auto f = fabric_tensor(w);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(f(a, b), a == b ? 1.0 / 3.0 : 0.0, 1e-12);
    EXPECT_EQ(contact_network(w).size(), 3u * 5u * 5u * 4u);
  }
  {
    World<3> w;
    const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 0.5));
    w.resolve_pair_laws();
    for (int a = 0; a < 6; ++a) w.particles.add(vec<3>(d * a, 0.0, 0.0), r, 1000.0, mat);
    build_neighbour_list(w);
    const auto f = fabric_tensor(w);
    EXPECT_NEAR(f(0, 0), 1.0, 1e-14);
    EXPECT_NEAR(fabric_anisotropy<3>(f), 3.0, 1e-12);
  }
}

}  // namespace
}  // namespace geodem::test
