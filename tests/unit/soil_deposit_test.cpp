// The settling test of the layered deposits (lab/soil_deposit.hpp): a soil counts as
// moving while its kinetic energy exceeds a tenth of sum(rho pi r^2 g r), i.e. for one
// disc while v^2 > 0.2 g r; and the layer statistics of a single disc kind.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lab/soil_deposit.hpp"

namespace geodem {
namespace {

TEST(SoilDeposit, MovingWhileTheKineticEnergyExceedsATenthOfTheDropByOneRadius) {
  World<2> w;
  w.gravity = Dim<2>::Vec(0.0, -9.81);
  const double r = 0.01, rho = 2600.0;
  w.particles.add(Dim<2>::Vec(0.0, 1.0), r, rho, 0);
  const double v_limit = std::sqrt(0.2 * 9.81 * r);
  w.particles.vel[0] = Dim<2>::Vec(0.0, -1.01 * v_limit);
  EXPECT_TRUE(soil_moving(w, rho));
  w.particles.vel[0] = Dim<2>::Vec(0.0, -0.99 * v_limit);
  EXPECT_FALSE(soil_moving(w, rho));
}

TEST(SoilDeposit, LayerStatisticsOfDiscs) {
  GrainSpec spec;  // round discs of one size
  const auto kinds = resolve_kinds<2>(spec);
  const GrainAreas a = grain_areas(kinds, 0.01, 0.0);
  // The resolved shapes' areas come from a quadrature (relative error about 1e-8).
  EXPECT_NEAR(a.mean, std::numbers::pi * 1e-4, 1e-7 * std::numbers::pi * 1e-4);
  EXPECT_NEAR(a.bound_ratio, 1.0, 1e-7);  // a disc is its own bounding disc
  // Radii uniform in r (1 +- f): the mean area grows by (1 + f^2 / 3).
  EXPECT_NEAR(grain_areas(kinds, 0.01, 0.3).mean / a.mean, 1.03, 1e-12);
}

}  // namespace
}  // namespace geodem
