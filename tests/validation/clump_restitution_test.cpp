// The restitution of a clump's collision (clumps/collision_shares.hpp): a collision between
// two bodies has the asked restitution e however many member contacts carry it at once.
// Frictionless linear law, no gravity, e = 0.5; the rebound speed of the centre of mass
// over the approach speed must equal e within 1 % (the oblique-impact test's tolerance for a
// single grain):
//  - a two-member clump landing flat on a floor (two contacts at once) and upright (one);
//  - in 3D a three-member clump lying flat (three contacts);
//  - two two-member clumps meeting side by side (two member pairs at once);
// Contacts at an angle to each other share the collision too, and the rule is then exact
// for the damping along each contact, not for the rebound: a grain landing in the notch
// between two members touches them at +-30 deg from the vertical; the vertical motion then
// has the stiffness 2 kn cos^2 30 and the dashpots 2 cos^2 30 c, c sized with half the
// reduced mass, so its damping ratio is beta cos 30 (beta of e): e' = exp(-pi b / sqrt(1 - b^2))
// with b = beta cos 30, 0.584 for e = 0.5 (1 %).
// Each member contact damped as a whole collision would give e = 0.366 for two flat contacts.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "clumps/clump_dynamics.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

constexpr double kKn = 1.0e5;
constexpr double kE = 0.5;
constexpr double kS = 0.01;  // member radius
constexpr double kV = 0.05;  // approach speed

template <typename T>
class ClumpRestitution : public ::testing::Test {};
TYPED_TEST_SUITE(ClumpRestitution, Dims, DimNames);

// Members of radius 1 (scaled by kS) at the given offsets, touching but not overlapping.
template <int D>
ResolvedClump<D> clump_template(std::initializer_list<Vec<D>> centres) {
  ClumpTemplate<D> t;
  for (const auto& c : centres) {
    t.centre.push_back(c);
    t.radius.push_back(1.0);
  }
  return resolve_clump(t);
}

template <int D>
World<D> world_with_floor(bool floor) {
  World<D> w;
  const auto mat = add_material(w, linear_material(kKn, 0.5 * kKn, 0.0, kE));
  if (floor) add_plane(w, Vec<D>::Zero(), axis<D>(1), mat, "floor");
  w.resolve_pair_laws();
  return w;
}

// Steps until the bodies touched and came apart again; the time step is 1/4000 of the
// shortest contact duration among the cases (pi sqrt(m/(3 kn)) for a grain of mass m).
template <int D>
void collide(World<D>& w) {
  const double m = 2600.0 * Dim<D>::volume(kS);
  w.dt = std::numbers::pi * std::sqrt(m / (3.0 * kKn)) / 4000.0;
  bool touched = false;
  for (int k = 0; k < 400000; ++k) {
    w.measure_this_step = true;
    step(w);
    const std::size_t n = w.stats.contacts + w.stats.wall_contacts;
    if (n > 0) touched = true;
    if (touched && n == 0) return;
  }
  FAIL() << "the collision did not end";
}

template <int D>
typename Dim<D>::Orient turned(double angle) {
  if constexpr (D == 2) {
    return angle;
  } else {
    return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Vec<3>::UnitZ()));
  }
}

// A clump falling at kV onto the floor; returns its rebound over approach speed.
template <int D>
double floor_rebound(const ResolvedClump<D>& t, const typename Dim<D>::Orient& q, double height) {
  World<D> w = world_with_floor<D>(true);
  add_clump(w, t, vec<D>(0.0, height, 0.0), q, kS, 2600.0, 0, vec<D>(0.0, -kV));
  collide(w);
  return w.clumps.vel[0][1] / kV;
}

TYPED_TEST(ClumpRestitution, TwoMembersLandingFlatOrUpright) {
  constexpr int D = TypeParam::value;
  const auto t = clump_template<D>({vec<D>(-1.0, 0.0), vec<D>(1.0, 0.0)});
  const double flat = floor_rebound<D>(t, turned<D>(0.0), 1.05 * kS);
  const double upright = floor_rebound<D>(t, turned<D>(std::numbers::pi / 2.0), 2.05 * kS);
  report(std::to_string(D) + "D clump flat on two members: restitution error", rel_err(flat, kE));
  report(std::to_string(D) + "D clump upright on one member: restitution error",
         rel_err(upright, kE));
  EXPECT_LT(rel_err(flat, kE), 0.01);
  EXPECT_LT(rel_err(upright, kE), 0.01);
}

TEST(ClumpRestitution3D, ThreeMembersLandingFlat) {
  const double h = std::sqrt(3.0);  // an equilateral triangle of side 2 in the x-z plane
  const auto t = clump_template<3>(
      {Vec<3>(-1.0, 0.0, -h / 3.0), Vec<3>(1.0, 0.0, -h / 3.0), Vec<3>(0.0, 0.0, 2.0 * h / 3.0)});
  // The body frame is the principal one: turn the axis normal to the members' plane (the
  // body axis along which every offset is zero) to the vertical.
  int normal = 0;
  for (int a = 0; a < 3; ++a) {
    bool in_plane = true;
    for (const auto& o : t.offset) in_plane = in_plane && std::abs(o[a]) < 1e-12;
    if (in_plane) normal = a;
  }
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(axis<3>(normal), axis<3>(1));
  const double e = floor_rebound<3>(t, q, 1.05 * kS);
  report("3D clump flat on three members: restitution error", rel_err(e, kE));
  EXPECT_LT(rel_err(e, kE), 0.01);
}

TYPED_TEST(ClumpRestitution, TwoClumpsSideBySide) {
  constexpr int D = TypeParam::value;
  World<D> w = world_with_floor<D>(false);
  const auto t = clump_template<D>({vec<D>(-1.0, 0.0), vec<D>(1.0, 0.0)});
  add_clump(w, t, vec<D>(0.0, 0.0, 0.0), turned<D>(0.0), kS, 2600.0, 0, vec<D>(0.0, kV));
  add_clump(w, t, vec<D>(0.0, 2.1 * kS, 0.0), turned<D>(0.0), kS, 2600.0, 0, vec<D>(0.0, -kV));
  collide(w);
  const double e = (w.clumps.vel[1][1] - w.clumps.vel[0][1]) / (2.0 * kV);
  report(std::to_string(D) + "D two clumps side by side: restitution error", rel_err(e, kE));
  EXPECT_LT(rel_err(e, kE), 0.01);
  EXPECT_LT(std::abs(spin_z<D>(w.clumps.angvel[0])) * kS, 1e-12);  // a symmetric impact
}

TYPED_TEST(ClumpRestitution, GrainInTheNotchOfAClump) {
  constexpr int D = TypeParam::value;
  World<D> w = world_with_floor<D>(false);
  const auto t = clump_template<D>({vec<D>(-1.0, 0.0), vec<D>(1.0, 0.0)});
  add_clump(w, t, Vec<D>::Zero(), turned<D>(0.0), kS, 2600.0, 0);
  // A grain of the members' radius above the notch, touching both members together.
  const double y = std::sqrt(3.0) * kS + 0.05 * kS;
  w.particles.add(vec<D>(0.0, y), kS, 2600.0, 0, vec<D>(0.0, -kV));
  const std::size_t g = w.particles.size() - 1;
  collide(w);
  const double e = (w.particles.vel[g][1] - w.clumps.vel[0][1]) / kV;
  const double b = damping_ratio(kE) * std::cos(std::numbers::pi / 6.0);
  const double e_want = std::exp(-std::numbers::pi * b / std::sqrt(1.0 - b * b));
  report(std::to_string(D) + "D grain in a clump's notch: restitution error", rel_err(e, e_want));
  EXPECT_LT(rel_err(e, e_want), 0.01);
}

}  // namespace
}  // namespace geodem::test
