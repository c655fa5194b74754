// The anchorage geometry and the analytic slippage estimate (lab/anchorage.hpp) against
// hand calculations: friction on both faces of a run-out, the at-rest lateral pressure on
// the trench part, the capstan factor at the bend; the sheet's nodes fall on its corners.
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

}  // namespace
}  // namespace geodem
