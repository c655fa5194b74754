// Rigid clumps (clumps/): conservation laws and rigid-body kinematics.
//  - Torque-free rotation of an asymmetric 3D clump (three unequal spheres, angular
//    momentum off the principal axes, so that the body tumbles): the world angular
//    momentum and the kinetic energy stay constant (1e-6 relative over 1e4 steps).
//  - Every member moves with its clump: v_m = v + omega x r_m, omega_m = omega (1e-12).
//  - Two frictionless elastic clumps collide off-centre: linear and angular momentum are
//    conserved to rounding, the kinetic energy after they separate to 1e-4.
//  - A clump comes to rest on a floor with its weight carried by it; members of one
//    clump never touch each other, even overlapping.
//  - Radius growth scales a clump homothetically: mass m^D, inertia m^(D+2).
//  - Renumbering grains (and so clumps) in cell order changes nothing but the order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "clumps/clump_dynamics.hpp"
#include "controllers/radius_growth.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class Clump : public ::testing::Test {};
TYPED_TEST_SUITE(Clump, Dims, DimNames);

template <int D>
ResolvedClump<D> pair_template(double distance) {
  ClumpTemplate<D> t;
  t.centre = {Vec<D>::Zero(), Vec<D>(distance * axis<D>(0))};
  t.radius = {1.0, 1.0};
  return resolve_clump(t);
}

ResolvedClump<3> asymmetric_template() {
  ClumpTemplate<3> t;
  t.centre = {Vec<3>(0.0, 0.0, 0.0), Vec<3>(1.3, 0.2, 0.0), Vec<3>(0.4, 1.0, 0.6)};
  t.radius = {1.0, 0.7, 0.5};
  return resolve_clump(t);
}

// World angular momentum of a clump about its centre of mass.
template <int D>
typename Dim<D>::Rot angular_momentum(const World<D>& w, std::size_t c) {
  if constexpr (D == 2) {
    return w.clumps.inertia[c] * w.clumps.angvel[c];
  } else {
    return w.clumps.angmom[c];
  }
}

// Sets a clump's angular momentum and the angular velocity it implies.
void set_angular_momentum(World<3>& w, std::size_t c, const Vec<3>& L) {
  auto& C = w.clumps;
  C.angmom[c] = L;
  const Vec<3> lb = C.orient[c].conjugate() * L;
  C.angvel[c] = C.orient[c] * Vec<3>(lb.cwiseQuotient(C.inertia[c]));
  place_members(w);
}

TEST(ClumpRotation, TorqueFreeAsymmetric3D) {
  World<3> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const auto t = asymmetric_template();
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.4, Vec<3>(1, 2, 3).normalized()));
  add_clump(w, t, Vec<3>(0.5, -0.2, 0.1), q, 0.01, 2600.0, mat, Vec<3>(0.1, 0.0, -0.05));
  // Angular momentum off every principal axis: the body tumbles.
  const auto& C = w.clumps;
  const Vec<3> L0 = Vec<3>(0.3, -0.5, 0.8).normalized() * 1e-6;
  set_angular_momentum(w, 0, L0);
  const double e0 = kinetic_energy(w);
  const double omega = C.angvel[0].norm();
  w.dt = 2e-3 / omega;  // |omega| dt = 2e-3: 3 revolutions in 1e4 steps
  const Vec<3> x0 = C.pos[0], v0 = C.vel[0];
  double worst_l = 0.0, worst_e = 0.0, swing = 0.0;
  const Vec<3> w0 = C.angvel[0];
  for (int k = 0; k < 10000; ++k) {
    step(w);
    worst_l = std::max(worst_l, (C.angmom[0] - L0).norm() / L0.norm());
    worst_e = std::max(worst_e, rel_err(kinetic_energy(w), e0));
    swing = std::max(swing, (C.angvel[0] - w0).norm() / w0.norm());
  }
  report("torque-free clump: angular momentum drift", worst_l);
  report("torque-free clump: kinetic energy error", worst_e);
  EXPECT_LT(worst_l, 1e-6);
  EXPECT_LT(worst_e, 1e-6);
  EXPECT_GT(swing, 0.1);  // the angular velocity does wander: a real tumble
  EXPECT_LT((C.pos[0] - (x0 + v0 * w.time)).norm(), 1e-12);
}

TYPED_TEST(Clump, MembersMoveRigidly) {
  constexpr int D = TypeParam::value;
  World<D> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const auto t = pair_template<D>(1.5);
  add_clump(w, t, vec<D>(0.1, 0.2, 0.3), Dim<D>::identity(), 0.01, 2600.0, mat, vec<D>(1, 2, 3));
  auto& C = w.clumps;
  if constexpr (D == 2) {
    C.angvel[0] = 7.0;
    place_members(w);
  } else {
    set_angular_momentum(w, 0, Vec<3>(1e-7, 2e-7, -3e-7));
  }
  w.dt = 1e-5;
  for (int k = 0; k < 100; ++k) step(w);
  const auto& P = w.particles;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const Vec<D> r = P.pos[i] - C.pos[0];
    const Vec<D> v = C.vel[0] + Dim<D>::cross(C.angvel[0], r);
    EXPECT_LT((P.vel[i] - v).norm(), 1e-12 * v.norm());
    EXPECT_LT(std::sqrt(Dim<D>::rot_norm2(P.angvel[i] - C.angvel[0])), 1e-12);
    EXPECT_NEAR(r.norm(), 0.0075, 1e-12);  // member offsets keep their length
  }
}

TYPED_TEST(Clump, ElasticCollisionConservesMomentaAndEnergy) {
  constexpr int D = TypeParam::value;
  World<D> w;
  const auto mat = add_material(w, linear_material(1e4, 5e3, 0.0, 1.0));
  w.resolve_pair_laws();
  const double s = 0.01;
  const auto t = pair_template<D>(1.6);
  // Off-centre: clump B sits higher, and is turned, so the impact spins both.
  add_clump(w, t, vec<D>(0.0, 0.0, 0.0), Dim<D>::identity(), s, 2600.0, mat, vec<D>(0.5, 0, 0));
  typename Dim<D>::Orient q;
  if constexpr (D == 2)
    q = 1.0;
  else
    q = Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Vec<3>(0.2, 0.3, 1.0).normalized()));
  add_clump(w, t, vec<D>(4.5 * s, 0.9 * s, 0.2 * s), q, s, 2600.0, mat);
  auto momentum = [&] {
    Vec<D> p = Vec<D>::Zero();
    for (std::size_t c = 0; c < 2; ++c) p += w.clumps.vel[c] / w.clumps.inv_mass[c];
    return p;
  };
  // Angular momentum about a point off the line of motion: orbital + spin.
  const Vec<D> origin = vec<D>(0.0, -3.0 * s, 0.0);
  auto ang_momentum = [&] {
    auto l = Dim<D>::zero_rot();
    for (std::size_t c = 0; c < 2; ++c)
      l += Dim<D>::cross(Vec<D>(w.clumps.pos[c] - origin),
                         Vec<D>(w.clumps.vel[c] / w.clumps.inv_mass[c])) +
           angular_momentum(w, c);
    return l;
  };
  const Vec<D> p0 = momentum();
  const auto l0 = ang_momentum();
  const double e0 = kinetic_energy(w);
  // A fixed step (an automatic one changing inside a collision spoils the leapfrog's
  // energy balance), about 1/40 of the critical step: the energy error falls as dt^2.
  w.dt = 2e-5;
  bool touched = false;
  for (int k = 0; k < 200000; ++k) {
    w.measure_this_step = true;
    step(w);
    if (w.stats.contacts > 0) touched = true;
    if (touched && w.stats.contacts == 0) break;
  }
  ASSERT_TRUE(touched);
  const double spin = std::sqrt(Dim<D>::rot_norm2(w.clumps.angvel[1]));
  EXPECT_GT(spin * s, 0.01);  // the impact did spin clump B
  const double pe = (momentum() - p0).norm() / p0.norm();
  const double le =
      std::sqrt(Dim<D>::rot_norm2(ang_momentum() - l0)) / std::sqrt(Dim<D>::rot_norm2(l0));
  const double ee = rel_err(kinetic_energy(w), e0);
  report(std::to_string(D) + "D clump collision: momentum error", pe);
  report(std::to_string(D) + "D clump collision: angular momentum error", le);
  report(std::to_string(D) + "D clump collision: kinetic energy error", ee);
  EXPECT_LT(pe, 1e-12);
  EXPECT_LT(le, 1e-9);
  EXPECT_LT(ee, 1e-4);
}

TYPED_TEST(Clump, RestsOnFloorAndMembersIgnoreEachOther) {
  constexpr int D = TypeParam::value;
  World<D> w;
  const double s = 0.01, rho = 2600.0, g = 9.81;
  const auto mat = add_material(w, modulus_material(1e7, 0.5, 0.5, 1.0, rho));
  add_plane(w, Vec<D>::Zero(), axis<D>(1), mat, "floor");
  w.resolve_pair_laws();
  // Overlapping members (centres 1.2 radii apart), dropped tilted from above the floor.
  const auto t = pair_template<D>(1.2);
  typename Dim<D>::Orient q;
  if constexpr (D == 2)
    q = 0.3;
  else
    q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec<3>(0.1, 0.2, 1.0).normalized()));
  add_clump(w, t, vec<D>(0.0, 3.0 * s, 0.0), q, s, rho, mat);
  w.gravity = vec<D>(0.0, -g);
  w.local_damping = 0.3;
  w.auto_dt = true;
  for (int k = 0; k < 40000; ++k) step(w);
  EXPECT_EQ(w.nlist.pair_count(), 0u);  // the two members are never paired
  const double weight = g / w.clumps.inv_mass[0];
  EXPECT_LT(rel_err(w.walls[0].force[1], -weight), 1e-4);
  // Lying flat: both members touch the floor at the same overlap.
  const auto& P = w.particles;
  EXPECT_NEAR(P.pos[0][1], P.pos[1][1], 1e-6 * s);
  EXPECT_LT(kinetic_energy(w), 1e-12 * weight * s);
}

TYPED_TEST(Clump, RadiusGrowthScalesHomothetically) {
  constexpr int D = TypeParam::value;
  World<D> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const auto t = pair_template<D>(1.5);
  add_clump(w, t, vec<D>(0.3, 0.1, 0.2), Dim<D>::identity(), 0.01, 2600.0, mat);
  const double m0 = 1.0 / w.clumps.inv_mass[0];
  const double i0 = Clumps<D>::min_moment(w.clumps.inertia[0]);
  const double f = 1.1;
  RadiusGrowth<D>::scale(w, f);
  w.dt = 1e-6;
  step(w);  // places the members
  EXPECT_LT(rel_err(1.0 / w.clumps.inv_mass[0], m0 * std::pow(f, D)), 1e-12);
  EXPECT_LT(rel_err(Clumps<D>::min_moment(w.clumps.inertia[0]), i0 * std::pow(f, D + 2)), 1e-12);
  const auto& P = w.particles;
  EXPECT_LT(rel_err((P.pos[1] - P.pos[0]).norm(), 0.015 * f), 1e-12);
  EXPECT_LT(rel_err(P.radius[0], 0.01 * f), 1e-12);
  EXPECT_LT((w.clumps.pos[0] - vec<D>(0.3, 0.1, 0.2)).norm(), 1e-15);
}

// Renumbering grains in cell order renumbers clumps with them: every member keeps its clump
// (by stable id), and a packing of clumps steps the same with and without renumbering.
TYPED_TEST(Clump, RenumberingKeepsMembersAndDynamics) {
  constexpr int D = TypeParam::value;
  auto make = [](int sort_interval) {
    World<D> w;
    const auto mat = add_material(w, modulus_material(1e7, 0.5, 0.5, 1.0));
    w.resolve_pair_laws();
    const auto t = pair_template<D>(1.8);
    std::mt19937_64 rng(3);
    // Bounding circles apart at first.
    const int side = D == 2 ? 8 : 4;
    throw_clumps_together(w, t, {side, side, side}, 0.04, 0.001, 5.0, mat, rng);
    w.dt = 1e-5;  // about 1/20 of the critical step
    w.sort_interval = sort_interval;
    return w;
  };
  World<D> a = make(0), b = make(1);
  std::vector<std::uint32_t> clump_of_id(a.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i)
    clump_of_id[a.particles.id[i]] = a.clumps.id[a.particles.clump[i]];
  std::size_t touching = 0;
  for (int k = 0; k < 8000; ++k) {
    a.measure_this_step = b.measure_this_step = true;
    step(a), step(b);
    touching = std::max(touching, b.stats.contacts);
  }
  EXPECT_GE(touching, 5u);  // the clumps did collide
  ASSERT_GT(b.nlist.builds, 1u);
  bool moved = false;
  for (std::size_t i = 0; i < b.particles.size(); ++i) {
    moved |= b.particles.id[i] != i;
    EXPECT_EQ(b.clumps.id[b.particles.clump[i]], clump_of_id[b.particles.id[i]]);
  }
  EXPECT_TRUE(moved);  // the renumbering did happen
  // Same trajectories (to rounding: sums run in another order).
  std::vector<Vec<D>> pos_a(a.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i)
    pos_a[a.particles.id[i]] = a.particles.pos[i];
  double worst = 0.0;
  for (std::size_t i = 0; i < b.particles.size(); ++i)
    worst = std::max(worst, (b.particles.pos[i] - pos_a[b.particles.id[i]]).norm());
  report(std::to_string(D) + "D clumps renumbered: largest position difference (m)", worst);
  EXPECT_LT(worst, 1e-12);
}

}  // namespace
}  // namespace geodem::test
