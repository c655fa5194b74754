// Elastic Hertz impacts of Chung & Ooi (2011), tests 1 and 2: largest force, largest
// overlap and contact duration against Hertz theory (spheres only: the Hertz law is 3D).
//
//   delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)
//   F_max     = 4/3 E* sqrt(R*) delta_max^(3/2)
//   t_c       = 2 I delta_max / v,  I = int_0^1 (1 - x^(5/2))^(-1/2) dx
//             = sqrt(pi) Gamma(7/5) / Gamma(9/10),  i.e. t_c = 2.868 (m*^2 / (R* E*^2 v))^(1/5)
//
// with v the relative approach speed.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "test_util.hpp"

namespace geodem::test {
namespace {

struct HertzTheory {
  double max_overlap, max_force, duration;
  HertzTheory(double mstar, double estar, double rstar, double v) {
    max_overlap = std::pow(15.0 * mstar * v * v / (16.0 * estar * std::sqrt(rstar)), 0.4);
    max_force = 4.0 / 3.0 * estar * std::sqrt(rstar) * std::pow(max_overlap, 1.5);
    const double integral = std::sqrt(std::numbers::pi) * std::tgamma(1.4) / std::tgamma(0.9);
    duration = 2.0 * integral * max_overlap / v;
  }
};

struct HertzCase {
  const char* name;
  double young, poisson, density;
};

// Test 1: two identical spheres, R = 0.01 m, each at 10 m/s towards the other.
const HertzCase kTest1[] = {{"glass", 4.8e10, 0.20, 2800.0}, {"limestone", 2.0e10, 0.25, 2500.0}};
// Test 2: a sphere of R = 0.1 m on a rigid flat wall at 0.2 m/s.
const HertzCase kTest2[] = {{"aluminium alloy", 7.0e10, 0.33, 2700.0},
                            {"magnesium alloy", 4.0e10, 0.35, 1800.0}};

void check_hertz(const ImpactResult& r, const HertzTheory& th, const std::string& tag) {
  const double err_f = rel_err(r.max_force, th.max_force);
  const double err_d = rel_err(r.max_overlap, th.max_overlap);
  const double err_t = rel_err(r.duration, th.duration);
  report(tag + " max force", err_f);
  report(tag + " max overlap", err_d);
  report(tag + " duration", err_t);
  EXPECT_LT(err_f, 0.01);
  EXPECT_LT(err_d, 0.01);
  EXPECT_LT(err_t, 0.01);
  // Elastic: the spheres leave at the approach speed.
  EXPECT_LT(rel_err(r.separation, r.approach), 1e-6);
}

TEST(HertzImpact, ChungOoiTest1TwoSpheres) {
  const double radius = 0.01, v = 20.0;  // relative speed: 10 m/s each
  for (const auto& c : kTest1) {
    SCOPED_TRACE(c.name);
    World<3> w;
    add_material(w, hertz_material(c.young, c.poisson, c.density));
    w.resolve_pair_laws();
    const double m = c.density * Dim<3>::volume(radius);
    const double mstar = 0.5 * m, rstar = 0.5 * radius;
    const double estar = c.young / (2.0 * (1.0 - c.poisson * c.poisson));
    const HertzTheory th(mstar, estar, rstar, v);
    w.dt = th.duration / 2000.0;
    place_pair(w, radius, radius, c.density, 0, v);
    EXPECT_NEAR(w.particles.vel[0].x(), 10.0, 1e-12);
    check_hertz(run_impact(w, 10000), th, std::string("Hertz test 1 ") + c.name);
  }
}

TEST(HertzImpact, ChungOoiTest2SphereOnRigidWall) {
  const double radius = 0.1, v = 0.2;
  for (const auto& c : kTest2) {
    SCOPED_TRACE(c.name);
    World<3> w;
    const auto grain = add_material(w, hertz_material(c.young, c.poisson, c.density));
    // A rigid wall: its compliance (1 - nu^2)/E vanishes next to the sphere's.
    const auto rigid = add_material(w, hertz_material(1e30, 0.3, 7800.0, 0.0, 1.0, "rigid"));
    add_plane(w, vec<3>(0.0, 0.0), vec<3>(0.0, 1.0), rigid, "floor");
    w.resolve_pair_laws();
    const double mstar = c.density * Dim<3>::volume(radius), rstar = radius;
    const double estar = c.young / (1.0 - c.poisson * c.poisson);
    EXPECT_LT(rel_err(w.wall_law(grain, 0).estar, estar), 1e-15);
    const HertzTheory th(mstar, estar, rstar, v);
    w.dt = th.duration / 2000.0;
    place_on_floor(w, radius, c.density, grain, v);
    check_hertz(run_impact(w, 10000), th, std::string("Hertz test 2 ") + c.name);
  }
}

// The closed-form duration constant quoted in the literature.
TEST(HertzImpact, DurationConstant) {
  const double integral = std::sqrt(std::numbers::pi) * std::tgamma(1.4) / std::tgamma(0.9);
  EXPECT_NEAR(2.0 * integral * std::pow(15.0 / 16.0, 0.4), 2.868, 5e-4);
}

}  // namespace
}  // namespace geodem::test
