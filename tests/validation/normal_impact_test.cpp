// Normal impact with the linear spring-dashpot law: contact duration, largest overlap and
// restitution against the closed-form damped oscillator, grain-grain and grain-wall.
// The force is not clamped to stay repulsive, so the model's restitution is exactly the
// requested e; only the time discretisation (dt = duration / 2000) separates them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "test_util.hpp"

namespace geodem::test {
namespace {

constexpr std::array<double, 6> kRestitutions = {0.1, 0.3, 0.5, 0.7, 0.9, 1.0};
constexpr double kKn = 1.0e6;  // N/m (3D), N/m per metre (2D)
constexpr double kDensity = 2600.0;
constexpr double kSpeed = 1.5;  // relative approach speed (m/s)

template <typename T>
class NormalImpact : public ::testing::Test {};
TYPED_TEST_SUITE(NormalImpact, Dims, DimNames);

// Checks one collision against the oscillator of mass mstar and reports the errors.
void check_linear_impact(const ImpactResult& r, double mstar, double e, const std::string& tag) {
  const LinearImpactTheory th(mstar, kKn, damping_ratio(e), kSpeed);
  const double err_e = rel_err(r.separation / r.approach, e);
  const double err_t = rel_err(r.duration, th.duration);
  const double err_d = rel_err(r.max_overlap, th.max_overlap);
  report(tag + " restitution", err_e);
  report(tag + " duration", err_t);
  report(tag + " max overlap", err_d);
  EXPECT_NEAR(r.approach, kSpeed, 1e-12);
  EXPECT_LT(err_e, 0.01);
  EXPECT_LT(err_t, 0.01);
  EXPECT_LT(err_d, 0.01);
  if (e == 1.0) {
    // The undamped closed forms of the brief: pi sqrt(m*/kn) and v sqrt(m*/kn).
    EXPECT_LT(rel_err(r.duration, std::numbers::pi * std::sqrt(mstar / kKn)), 1e-4);
    EXPECT_LT(rel_err(r.max_overlap, kSpeed * std::sqrt(mstar / kKn)), 1e-4);
    EXPECT_LT(err_e, 1e-4);
  }
}

TYPED_TEST(NormalImpact, GrainGrainLinear) {
  constexpr int D = TypeParam::value;
  const double r1 = 0.01, r2 = 0.006;
  const double m1 = kDensity * Dim<D>::volume(r1), m2 = kDensity * Dim<D>::volume(r2);
  const double mstar = m1 * m2 / (m1 + m2);
  for (double e : kRestitutions) {
    SCOPED_TRACE("e = " + std::to_string(e));
    World<D> w;
    add_material(w, linear_material(kKn, 0.5 * kKn, 0.5, e, kDensity));
    w.resolve_pair_laws();
    const LinearImpactTheory th(mstar, kKn, damping_ratio(e), kSpeed);
    w.dt = th.duration / 2000.0;
    place_pair(w, r1, r2, kDensity, 0, kSpeed);
    const ImpactResult r = run_impact(w, 10000);
    check_linear_impact(r, mstar, e, std::to_string(D) + "D grain-grain e=" + std::to_string(e));
    // Momentum is conserved exactly by the pairwise forces.
    EXPECT_NEAR((m1 * w.particles.vel[0] + m2 * w.particles.vel[1]).norm(), 0.0,
                1e-12 * m1 * kSpeed);
  }
}

TYPED_TEST(NormalImpact, GrainWallLinear) {
  constexpr int D = TypeParam::value;
  const double radius = 0.008;
  const double m = kDensity * Dim<D>::volume(radius);
  for (double e : kRestitutions) {
    SCOPED_TRACE("e = " + std::to_string(e));
    World<D> w;
    const auto grain = add_material(w, linear_material(kKn, 0.5 * kKn, 0.5, e, kDensity));
    const auto wall = add_material(w, linear_material(kKn, 0.5 * kKn, 0.5, 1.0, kDensity));
    add_plane(w, vec<D>(0.0, 0.0), vec<D>(0.0, 1.0), wall, "floor");
    w.resolve_pair_laws();
    const LinearImpactTheory th(m, kKn, damping_ratio(e), kSpeed);
    w.dt = th.duration / 2000.0;
    place_on_floor(w, radius, kDensity, grain, kSpeed);
    const ImpactResult r = run_impact(w, 10000);
    check_linear_impact(r, m, e, std::to_string(D) + "D grain-wall e=" + std::to_string(e));
  }
}

}  // namespace
}  // namespace geodem::test
