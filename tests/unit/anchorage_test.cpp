// The anchorage geometry and the design estimates (lab/anchorage.hpp) against hand
// calculations: friction on both faces of a run-out, the at-rest lateral pressure on the
// trench part, the capstan factor at the bend, adhesion; the soil-mass estimate with the
// soil's strength and no capstan; the sheet's nodes fall on its corners, or on the arc
// round a rounded trench edge.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "lab/anchorage.hpp"

namespace geodem {
namespace {

constexpr double kTanDelta = 0.6745;  // tan(34 deg)

AnchorGeometry anchor(std::string shape) {
  AnchorGeometry g;
  g.shape = std::move(shape);
  return g;
}

TEST(Anchorage, RunoutIsFrictionOnBothFaces) {
  AnchorGeometry g = anchor("runout");
  g.runout_length = 1.0;
  g.cover = 0.3;
  const double gamma = 16700.0, q = 5000.0;
  const SlipEstimate e = slip_estimate(g, gamma, q, kTanDelta, 0.5);
  EXPECT_DOUBLE_EQ(e.sigma_v0, gamma * 0.3 + q);
  EXPECT_NEAR(e.tension, 2.0 * 1.0 * (gamma * 0.3 + q) * kTanDelta, 1e-9);
  EXPECT_DOUBLE_EQ(e.capstan, 1.0);
}

TEST(Anchorage, LShapeAddsTheTrenchWallRoundACapstan) {
  AnchorGeometry g = anchor("L");
  g.runout_length = 1.0;
  g.cover = 0.3;
  g.trench_depth = 0.5;
  g.trench_width = 0.3;
  const double gamma = 16700.0, K = 1.0 - std::sin(41.0 * std::numbers::pi / 180.0);
  const SlipEstimate e = slip_estimate(g, gamma, 0.0, kTanDelta, K);
  const double sv0 = gamma * 0.3;
  // Lateral pressure K (sv0 + gamma z) integrated over the depth, on both faces.
  const double trench = 2.0 * kTanDelta * K * (sv0 * 0.5 + gamma * 0.5 * 0.5 / 2.0);
  const double capstan = std::exp(0.5 * std::numbers::pi * kTanDelta);
  EXPECT_NEAR(e.trench, trench, 1e-9 * trench);
  EXPECT_NEAR(e.capstan, capstan, 1e-12);
  EXPECT_NEAR(e.tension, 2.0 * sv0 * kTanDelta + capstan * trench, 1e-9 * e.tension);
}

TEST(Anchorage, VShapeUsesTheNormalStressOnTheFlank) {
  AnchorGeometry g = anchor("V");
  g.runout_length = 1.0;
  g.cover = 0.2;
  g.trench_depth = 0.4;
  g.trench_width = 0.8;  // flank at 45 deg
  const double gamma = 18500.0, K = 0.45;
  const SlipEstimate e = slip_estimate(g, gamma, 0.0, kTanDelta, K);
  const double l = std::sqrt(0.4 * 0.4 + 0.4 * 0.4), sv0 = gamma * 0.2;
  const double sn_factor = 0.5 + 0.5 * K;  // cos^2 + K sin^2 at 45 deg
  const double trench =
      2.0 * kTanDelta * sn_factor * (sv0 * l + 0.5 * gamma * l * l * std::sqrt(0.5));
  EXPECT_NEAR(e.trench, trench, 1e-9 * trench);
  EXPECT_NEAR(e.capstan, std::exp(0.25 * std::numbers::pi * kTanDelta), 1e-12);
}

// The paper's L anchor in hand-computed numbers (docs/lab_tests.md, "Design methods"):
// run-out 1.0 m under 0.3 m of cover, 0.5 m down the trench, no surcharge.
// Sand: gamma 16.7 kN/m3, phi 41 deg, c 0, delta 34 deg, a 0, K0 = 1 - sin 41 = 0.34394.
//   sigma_v0 = 5010 Pa; slip: F1 = 2 x 5010 x 0.67451 = 6758.6 N/m,
//   F2 = 2 x 0.67451 x 0.34394 x (5010 x 0.5 + 16700 x 0.25 / 2) = 2130.8 N/m,
//   capstan exp(pi/2 x 0.67451) = 2.8850: T_slip = 6758.6 + 2.8850 x 2130.8 = 12906 N/m;
//   soil: tan 41 = 0.86929: F1 = 8710.3, F2 = 2746.2 (no capstan): T_soil = 11456 N/m.
// Silt: gamma 18.5 kN/m3, phi 34 deg, c 13 kPa, delta 34 deg, a 0, K0 = 0.44081.
//   sigma_v0 = 5550 Pa; slip: F1 = 7487.0, F2 = 2 x 0.67451 x 0.44081 x 5087.5 = 3025.3,
//   T_slip = 7487.0 + 2.8850 x 3025.3 = 16215 N/m;
//   soil: F1 = 26000 + 7487.0, F2 = 13000 + 3025.3: T_soil = 49512 N/m.
TEST(Anchorage, DesignHypothesesOfTheLAnchorByHand) {
  AnchorGeometry g = anchor("L");
  g.runout_length = 1.0;
  g.cover = 0.3;
  g.trench_depth = 0.5;
  g.trench_width = 0.3;
  const double deg = std::numbers::pi / 180.0;
  const double K_sand = 1.0 - std::sin(41.0 * deg), K_silt = 1.0 - std::sin(34.0 * deg);
  const double tan34 = std::tan(34.0 * deg), tan41 = std::tan(41.0 * deg);
  const SlipEstimate slip_sand = slip_estimate(g, 16700.0, 0.0, tan34, K_sand);
  const AnchorEstimate soil_sand = soil_estimate(g, 16700.0, 0.0, tan41, 0.0, K_sand);
  EXPECT_NEAR(slip_sand.runout, 6758.6, 0.1);
  EXPECT_NEAR(slip_sand.trench, 2130.8, 0.1);
  EXPECT_NEAR(slip_sand.capstan, 2.8850, 1e-4);
  EXPECT_NEAR(slip_sand.tension, 12906.0, 1.0);
  EXPECT_NEAR(soil_sand.runout, 8710.3, 0.1);
  EXPECT_NEAR(soil_sand.trench, 2746.2, 0.1);
  EXPECT_DOUBLE_EQ(soil_sand.capstan, 1.0);
  EXPECT_NEAR(soil_sand.tension, 11456.0, 1.0);
  EXPECT_LT(soil_sand.tension, slip_sand.tension);  // the sand's soil mass gives way first
  const SlipEstimate slip_silt = slip_estimate(g, 18500.0, 0.0, tan34, K_silt);
  const AnchorEstimate soil_silt = soil_estimate(g, 18500.0, 0.0, tan34, 13000.0, K_silt);
  EXPECT_NEAR(slip_silt.runout, 7487.0, 0.1);
  EXPECT_NEAR(slip_silt.trench, 3025.3, 0.1);
  EXPECT_NEAR(slip_silt.tension, 16215.0, 1.0);
  EXPECT_NEAR(soil_silt.tension, 49512.0, 1.0);
  EXPECT_GT(soil_silt.tension, slip_silt.tension);  // the silt's sheet slips first
}

TEST(Anchorage, AdhesionActsOnBothFacesOfEveryPart) {
  AnchorGeometry g = anchor("V");
  g.runout_length = 0.8;
  g.cover = 0.2;
  g.trench_depth = 0.3;
  g.trench_width = 0.8;  // flank of length 0.5 m
  const double a = 2000.0;
  const SlipEstimate with = slip_estimate(g, 18000.0, 1000.0, kTanDelta, 0.5, -1.0, a);
  const SlipEstimate without = slip_estimate(g, 18000.0, 1000.0, kTanDelta, 0.5);
  EXPECT_NEAR(with.runout - without.runout, 2.0 * a * 0.8, 1e-9);
  EXPECT_NEAR(with.trench - without.trench, 2.0 * a * 0.5, 1e-9);
  EXPECT_NEAR(with.tension - without.tension, 2.0 * a * (0.8 + with.capstan * 0.5), 1e-9);
  // A run-out is never governed by the soil mass when phi >= delta and c >= a.
  g = anchor("runout");
  EXPECT_GE(soil_estimate(g, 18000.0, 0.0, kTanDelta, 0.0, 0.5).tension,
            slip_estimate(g, 18000.0, 0.0, kTanDelta, 0.5).tension);
}

TEST(Anchorage, NodesOnEveryCornerAndTrenchRegions) {
  AnchorGeometry g = anchor("L");
  g.runout_length = 1.0;
  g.trench_depth = 0.5;
  g.trench_width = 0.3;
  g.free_length = 0.05;
  const auto corners = sheet_corners(g, 0.7);
  ASSERT_EQ(corners.size(), 3u);
  const auto nodes = sheet_nodes(corners, 0.024);
  for (const auto& c : corners) {
    bool found = false;
    for (const auto& n : nodes) found |= (n - c).norm() < 1e-12;
    EXPECT_TRUE(found);
  }
  for (std::size_t k = 0; k + 1 < nodes.size(); ++k)
    EXPECT_LE((nodes[k + 1] - nodes[k]).norm(), 0.024 + 1e-12);
  // The trench lies behind the sheet's vertical part, below the run-out level.
  EXPECT_TRUE(overlaps_trench(g, 0.7, Point2(1.15, 0.5), 0.01));
  EXPECT_FALSE(overlaps_trench(g, 0.7, Point2(0.9, 0.5), 0.01));
  EXPECT_TRUE(overlaps_trench(g, 0.7, Point2(0.995, 0.5), 0.01));
  EXPECT_FALSE(overlaps_trench(g, 0.7, Point2(1.15, 0.15), 0.01));
  g = anchor("V");
  g.runout_length = 1.0;
  g.trench_depth = 0.5;
  g.trench_width = 1.0;
  EXPECT_TRUE(overlaps_trench(g, 0.7, Point2(1.5, 0.5), 0.0));
  EXPECT_FALSE(overlaps_trench(g, 0.7, Point2(1.1, 0.3), 0.01));
}

// Turn from segment (a, b) to segment (b, c), clockwise negative.
double turn(const Point2& a, const Point2& b, const Point2& c) {
  const Point2 u = b - a, v = c - b;
  return std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
}

TEST(Anchorage, RoundedEdgeLaysTheSheetOnAnArc) {
  for (const char* shape : {"L", "V"}) {
    AnchorGeometry g = anchor(shape);
    g.runout_length = 1.0;
    g.trench_depth = 0.5;
    g.trench_width = std::string(shape) == "V" ? 0.8 : 0.3;
    g.free_length = 0.05;
    g.edge_radius = 0.1;
    const double y0 = 0.7, L = 0.024;
    const auto b = sheet_bend(g, y0);
    ASSERT_TRUE(b.has_value());
    const double beta = std::string(shape) == "V" ? std::atan2(0.5, 0.4) : 0.5 * std::numbers::pi;
    EXPECT_NEAR(b->turn, beta, 1e-12);
    // The arc touches the run-out and the trench side a radius from its centre, at
    // tan(beta / 2) x radius from the corner.
    const double reach = 0.1 * std::tan(0.5 * beta);
    EXPECT_NEAR((b->start - b->corner).norm(), reach, 1e-12);
    EXPECT_NEAR((b->end - b->corner).norm(), reach, 1e-12);
    EXPECT_NEAR(b->start.y(), y0, 1e-12);
    EXPECT_NEAR((b->centre - b->start).norm(), 0.1, 1e-12);
    EXPECT_NEAR((b->centre - b->end).norm(), 0.1, 1e-12);
    EXPECT_NEAR((b->centre - b->middle).norm(), 0.1, 1e-12);
    const auto nodes = sheet_path_nodes(g, y0, L);
    // Every node on the run-out, the arc or the trench side; no element longer than L;
    // the turns add up to the bend, and the arc's are equal.
    double total = 0.0, arc_turn = -1.0;
    int arc_nodes = 0;
    for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
      EXPECT_LE((nodes[k + 1] - nodes[k]).norm(), L + 1e-12);
      if (k == 0) continue;
      const double t = turn(nodes[k - 1], nodes[k], nodes[k + 1]);
      total += t;
      if (std::abs(t) > 1e-9) {
        ++arc_nodes;
        EXPECT_NEAR((nodes[k] - b->centre).norm(), 0.1, 1e-12);
        // The arc's first and last nodes turn by half a piece: the straight parts are
        // tangent to it.
        const bool end_of_arc =
            (nodes[k] - b->start).norm() < 1e-12 || (nodes[k] - b->end).norm() < 1e-12;
        if (!end_of_arc) {
          if (arc_turn < 0.0) arc_turn = std::abs(t);
          EXPECT_NEAR(std::abs(t), arc_turn, 1e-9);
        }
      }
    }
    EXPECT_NEAR(total, -beta, 1e-9);
    EXPECT_GE(arc_nodes, static_cast<int>(std::ceil(0.1 * beta / L)));
    // The foundation outside the arc is cut away; inside it stays.
    const Point2 outside = b->centre + 0.099 * (b->middle - b->centre).normalized();
    EXPECT_TRUE(overlaps_trench(g, y0, outside, 0.002));
    EXPECT_FALSE(overlaps_trench(g, y0, outside, 0.0));
    EXPECT_FALSE(overlaps_trench(g, y0, b->centre, 0.05));
    EXPECT_TRUE(overlaps_trench(g, y0, b->corner - Point2(0.005, 0.005), 0.0));
    // The foundation behind the trench stays up to the run-out level (the arc's angle alone,
    // an unbounded sector, once cut it down to the arc's centre, a radius lower).
    for (double x : {g.runout_length + g.trench_width + 0.02, 1.95})
      EXPECT_FALSE(overlaps_trench(g, y0, Point2(x, y0 - 0.03), 0.01)) << shape << " x " << x;
  }
  // A sharp edge: no arc, the nodes of sheet_nodes.
  AnchorGeometry g = anchor("L");
  g.runout_length = 1.0;
  g.trench_depth = 0.5;
  g.trench_width = 0.3;
  EXPECT_EQ(sheet_path_nodes(g, 0.7, 0.024), sheet_nodes(sheet_corners(g, 0.7), 0.024));
  EXPECT_EQ(sheet_bend(g, 0.7)->middle, sheet_bend(g, 0.7)->corner);
  EXPECT_FALSE(sheet_bend(anchor("runout"), 0.7).has_value());
}

}  // namespace
}  // namespace geodem
