// The settling test of the layered deposits (lab/soil_deposit.hpp): a soil counts as
// moving while its kinetic energy exceeds a tenth of sum(rho pi r^2 g r), i.e. for one
// disc while v^2 > 0.2 g r; the layer statistics of a single disc kind; the measures of
// the pull-out mechanism (lab/anchorage_mechanism.hpp); the weight of the soil above the
// interface shear box's sheet (lab/interface_box.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "clumps/clump_template.hpp"
#include "clumps/clumps.hpp"
#include "lab/anchorage_mechanism.hpp"
#include "lab/interface_box.hpp"
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

// The weight above a level counts the discs whose centre is at or above it and the clumps whose
// every member is: rho pi r^2 g for a disc, rho A g for a clump (its mass from its template).
TEST(InterfaceBox, WeightAboveALevelTakesWholeClumpsOnly) {
  using Vec = Dim<2>::Vec;
  World<2> w;
  w.gravity = Vec(0.0, -9.81);
  const double rho = 2000.0, g = 9.81;
  w.particles.add(Vec(0.0, 0.10), 0.01, rho, 0);   // above
  w.particles.add(Vec(0.1, -0.10), 0.02, rho, 0);  // below
  ClumpTemplate<2> t;
  t.centre = {Vec::Zero(), Vec(0.0, 1.4)};
  t.radius = {1.0, 0.8};
  const ResolvedClump<2> pair = resolve_clump(t);
  const double scale = 0.01;
  add_clump(w, pair, Vec(0.3, 0.05), Dim<2>::identity(), scale, rho, 0);    // wholly above
  add_clump(w, pair, Vec(0.5, -0.005), Dim<2>::identity(), scale, rho, 0);  // one member below
  std::vector<double> second;  // the second clump's members' heights: across the level 0
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    if (w.particles.member(i) && w.particles.clump[i] == 1)
      second.push_back(w.particles.pos[i].y());
  ASSERT_EQ(second.size(), 2u);
  EXPECT_LT(std::min(second[0], second[1]), 0.0);
  EXPECT_GT(std::max(second[0], second[1]), 0.0);
  const double disc = rho * std::numbers::pi * 1e-4 * g;
  const double clump = g / w.clumps.inv_mass[0];
  EXPECT_NEAR(clump, rho * pair.volume * scale * scale * g, 1e-12 * clump);
  EXPECT_NEAR(grains_weight_above(w, 0.0), disc + clump, 1e-12 * (disc + clump));
  const double all = disc + rho * std::numbers::pi * 4e-4 * g + 2.0 * clump;
  EXPECT_NEAR(grains_weight(w), all, 1e-12 * all);
  EXPECT_EQ(grains_weight_above(w, 1.0), 0.0);
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
