// The split of a pulled sheet into run-out, bend and trench part (lab/sheet_parts.hpp),
// checked on an L-shaped chain whose tensions and contact normals are set by hand: the
// partition by distance to the corner, the parts' carried tensions summing to the clamp's
// tension exactly (they telescope), the bend's tension ratio and the mobilised friction.
#include <gtest/gtest.h>

#include "lab/sheet_parts.hpp"

namespace geodem {
namespace {

using Vec = Dim<2>::Vec;

// An L: 6 elements of 0.1 m along x from (0, 0) to the corner (0.6, 0), then 4 down to
// (0.6, -0.4). Element k has tension 100 - 10 k and contact normal 1 + k.
SparChains<2> l_sheet() {
  SparChains<2> s;
  std::vector<Vec> pts;
  for (int k = 0; k <= 6; ++k) pts.emplace_back(0.1 * k, 0.0);
  for (int k = 1; k <= 4; ++k) pts.emplace_back(0.6, -0.1 * k);
  s.add_chain("sheet", pts, 1e5, 0.5, 0.002, 0);
  s.contact_normal.resize(s.elements());
  for (std::size_t e = 0; e < s.elements(); ++e)
    s.tension[e] = 100.0 - 10.0 * static_cast<double>(e),
    s.contact_normal[e] = 1.0 + static_cast<double>(e);
  return s;
}

TEST(SheetParts, SplitsAnLAtItsCorner) {
  const SparChains<2> s = l_sheet();
  // Band 0.06: the midpoints (0.55, 0) and (0.6, -0.05) are 0.05 from the corner, the next
  // ones 0.15: elements 5 and 6 form the bend.
  const SheetPartLoads p = sheet_part_loads(s, Vec(0.6, 0.0), 0.06);
  EXPECT_DOUBLE_EQ(p.carried[kRunoutPart], 100.0 - 50.0);  // tension[0] - tension[5]
  EXPECT_DOUBLE_EQ(p.carried[kBendPart], 50.0 - 30.0);     // tension[5] - tension[7]
  EXPECT_DOUBLE_EQ(p.carried[kTrenchPart], 30.0);          // to the free end
  EXPECT_DOUBLE_EQ(p.carried[0] + p.carried[1] + p.carried[2], s.tension[0]);
  EXPECT_DOUBLE_EQ(p.normal[kRunoutPart], 1 + 2 + 3 + 4 + 5);
  EXPECT_DOUBLE_EQ(p.normal[kBendPart], 6 + 7);
  EXPECT_DOUBLE_EQ(p.normal[kTrenchPart], 8 + 9 + 10);
  EXPECT_DOUBLE_EQ(p.bend_ratio(), 50.0 / 30.0);
  EXPECT_DOUBLE_EQ(p.mobilised(kRunoutPart), 50.0 / 15.0);
  EXPECT_DOUBLE_EQ(p.mobilised(kTrenchPart), 30.0 / 27.0);
}

TEST(SheetParts, NarrowBandTakesTheNearestElement) {
  const SparChains<2> s = l_sheet();
  // No midpoint within 0.01: the nearest (element 5, the first at 0.05) is the bend.
  const SheetPartLoads p = sheet_part_loads(s, Vec(0.6, 0.0), 0.01);
  EXPECT_DOUBLE_EQ(p.carried[kRunoutPart], 50.0);
  EXPECT_DOUBLE_EQ(p.carried[kBendPart], 10.0);
  EXPECT_DOUBLE_EQ(p.carried[kTrenchPart], 40.0);
  EXPECT_DOUBLE_EQ(p.normal[kBendPart], 6.0);
}

TEST(SheetParts, WithoutACornerAllIsRunout) {
  const SparChains<2> s = l_sheet();
  const SheetPartLoads p = sheet_part_loads(s, std::nullopt, 0.06);
  EXPECT_DOUBLE_EQ(p.carried[kRunoutPart], 100.0);
  EXPECT_DOUBLE_EQ(p.carried[kBendPart] + p.carried[kTrenchPart], 0.0);
  EXPECT_DOUBLE_EQ(p.normal[kRunoutPart], 55.0);
  EXPECT_DOUBLE_EQ(p.bend_ratio(), 0.0);  // nothing reaches past a bend
  EXPECT_DOUBLE_EQ(p.mobilised(kTrenchPart), 0.0);
}

TEST(SheetParts, RowMeansAreScaledSums) {
  const SparChains<2> s = l_sheet();
  SheetPartLoads sum;
  sum += sheet_part_loads(s, Vec(0.6, 0.0), 0.06);
  sum += sheet_part_loads(s, Vec(0.6, 0.0), 0.06);
  const SheetPartLoads mean = sum.scaled(0.5);
  EXPECT_DOUBLE_EQ(mean.carried[kBendPart], 20.0);
  EXPECT_DOUBLE_EQ(mean.normal[kTrenchPart], 27.0);
}

}  // namespace
}  // namespace geodem
