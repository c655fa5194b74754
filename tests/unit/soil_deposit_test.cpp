// The settling test of the layered deposits (lab/soil_deposit.hpp): a soil counts as
// moving while its kinetic energy exceeds a tenth of sum(rho pi r^2 g r), i.e. for one
// disc while v^2 > 0.2 g r; the layer statistics of a single disc kind; the measures of
// the pull-out mechanism (lab/anchorage_mechanism.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lab/anchorage_mechanism.hpp"
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

// The mechanism measures on a flat sheet from x = -0.1 to 1 at y = 0: grains within reach
// of it, mean displacements by id, and the classification's two thresholds.
TEST(AnchorageMechanism, MeasuresAndClassification) {
  using Vec = Dim<2>::Vec;
  World<2> w;
  w.spars.add_chain("sheet", {Vec(-0.1, 0.0), Vec(0.5, 0.0), Vec(1.0, 0.0)}, 1e5, 0.5, 0.002, 0);
  for (double y : {0.01, 0.03, 0.2}) w.particles.add(Vec(0.4, y), 0.01, 2600.0, 0);
  const std::vector<char> near = grains_near_sheet(w.particles, w.spars, 0.025);
  EXPECT_EQ(near, (std::vector<char>{1, 0, 0}));
  const std::vector<Vec> start = w.particles.pos;
  const std::vector<Vec> nodes = w.spars.pos;
  w.particles.pos[0] += Vec(-0.003, 0.004);  // moved 5 mm
  w.particles.pos[2] += Vec(-1.0, 0.0);      // not selected
  EXPECT_NEAR(mean_grain_displacement(w.particles, near, start), 0.005, 1e-15);
  for (auto& x : w.spars.pos) x += Vec(-0.02, 0.0);
  // Nodes inside the box (x > 0 at the start): two of three, each moved 20 mm.
  EXPECT_NEAR(mean_embedded_node_displacement(w, nodes), 0.02, 1e-15);
  EXPECT_EQ(classify_mechanism(0.049, 0.51).name, "slippage");
  EXPECT_EQ(classify_mechanism(0.051, 0.9).name, "soil_mass");
  EXPECT_EQ(classify_mechanism(0.01, 0.49).name, "soil_mass");
}

}  // namespace
}  // namespace geodem
