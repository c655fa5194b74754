// The calibration search against synthetic soils whose micro-macro relations are known
// and coupled (friction raises cohesion, bonds raise friction, kt/kn raises the modulus,
// rolling resistance raises peak and residual friction): it must reach every target
// within its tolerance, from a poor start, in a few evaluations (docs/studies.md).
#include <gtest/gtest.h>

#include <cmath>

#include "study/calibration_search.hpp"

namespace geodem {
namespace {

MacroValues synthetic_soil(const MicroParameters& p) {
  MacroValues m;
  m.phi_peak_deg = 10.0 + 0.55 * p.friction_deg + 8.0 * p.rolling_friction +
                   0.8 * std::log1p(p.bond_strength / 1e4);
  m.cohesion = 0.15 * p.bond_strength * (1.0 + 0.01 * (p.friction_deg - 30.0));
  m.young_modulus = 0.45 * p.young * (0.6 + 0.8 * p.kt_over_kn);
  m.poisson_ratio = 0.45 - 0.12 * std::log1p(2.0 * p.kt_over_kn);
  m.phi_residual_deg = 8.0 + 0.4 * p.friction_deg + 20.0 * p.rolling_friction;
  return m;
}

TEST(SecantStep, SolvesALinearRelationInTwoSteps) {
  SecantStep s(1.0, 100.0, -1e9, 1e9);  // default slope 1, true slope 3
  auto y = [](double x) { return 3.0 * x + 2.0; };
  double x = 0.0;
  x = s.next(x, y(x), 11.0);  // default slope: x = 9
  EXPECT_DOUBLE_EQ(x, 9.0);
  x = s.next(x, y(x), 11.0);  // secant: exact
  EXPECT_NEAR(y(x), 11.0, 1e-12);
}

TEST(SecantStep, LimitsTheStepKeepsBoundsAndIgnoresAWrongSignedSecant) {
  SecantStep s(1.0, 2.0, 0.0, 5.0);
  EXPECT_DOUBLE_EQ(s.next(1.0, 0.0, 10.0), 3.0);  // step limited to 2
  // Noise: y fell while x rose; the secant (-ve) is ignored for the default slope 1,
  // and the result is held at the upper bound.
  EXPECT_DOUBLE_EQ(s.next(3.0, -1.0, 10.0), 5.0);
}

TEST(SecantStep, AveragesTheSlopeOverTheLastFourPoints) {
  // y = 2x with noise +-0.1: the last two points alone give a slope of 1.8, the least
  // squares of the four give 1.96 (sxy = 9.8, sxx = 5).
  SecantStep s(1.0, 100.0, -1e9, 1e9);
  const double ys[] = {0.1, 1.9, 4.1, 5.9};
  double x = 0.0;
  for (int k = 0; k < 3; ++k) s.next(k, ys[k], 10.0);
  x = s.next(3.0, ys[3], 10.0);
  EXPECT_NEAR(x, 3.0 + 4.1 / 1.96, 1e-12);
}

TEST(CalibrationSearch, ReachesCoupledTargetsFromAPoorStart) {
  CalibrationTargets t;
  t.phi_peak_deg = 34.0;
  t.cohesion = 13e3;
  t.young_modulus = 1.5e7;
  t.poisson_ratio = 0.3;
  t.phi_residual_deg = 25.0;
  const SearchTolerances tol{0.5, 500.0, 0.05, 0.02};
  MicroParameters start;
  start.young = 1e8;
  start.kt_over_kn = 0.1;
  start.friction_deg = 20.0;
  start.bond_strength = 5e3;
  start.rolling_friction = 0.0;
  CalibrationSearch search(t, tol, start);
  EXPECT_TRUE(search.searches_bonds());
  int evaluations = 0;
  bool met = false;
  while (!met && evaluations < 12) {
    met = search.record(synthetic_soil(search.current()));
    ++evaluations;
  }
  ASSERT_TRUE(met) << "not met after " << evaluations << " evaluations";
  EXPECT_LE(evaluations, 10);
  const MacroValues m = synthetic_soil(search.current());
  EXPECT_NEAR(m.phi_peak_deg, 34.0, 0.5);
  EXPECT_NEAR(m.cohesion, 13e3, 500.0);
  EXPECT_NEAR(m.young_modulus / 1.5e7, 1.0, 0.05);
  EXPECT_NEAR(m.poisson_ratio, 0.3, 0.02);
  EXPECT_NEAR(m.phi_residual_deg, 25.0, 0.5);
  EXPECT_LE(search.miss(m), 1.0);
}

TEST(CalibrationSearch, FrictionalSoilKeepsNoBondsAndUntargetedParameters) {
  CalibrationTargets t;
  t.phi_peak_deg = 41.0;  // cohesion 0; no modulus, Poisson or residual target
  MicroParameters start;
  start.young = 2e7;
  start.kt_over_kn = 0.5;
  start.friction_deg = 30.0;
  start.rolling_friction = 0.3;
  CalibrationSearch search(t, {}, start);
  EXPECT_FALSE(search.searches_bonds());
  int evaluations = 0;
  while (!search.record(synthetic_soil(search.current())) && ++evaluations < 10) {
  }
  EXPECT_NEAR(synthetic_soil(search.current()).phi_peak_deg, 41.0, 0.5);
  EXPECT_EQ(search.current().bond_strength, 0.0);
  EXPECT_EQ(search.current().young, 2e7);
  EXPECT_EQ(search.current().kt_over_kn, 0.5);
  EXPECT_EQ(search.current().rolling_friction, 0.3);
}

}  // namespace
}  // namespace geodem
