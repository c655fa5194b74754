// The direct shear box's frames (lab/direct_shear_box.hpp): the side walls split at the
// split plane, the upper frame's sides and lip lifted by the gap, the lips reaching `travel`
// past the sides, and the frames' shear force the mean of the two frames' x-forces; in 3D the
// same with rectangles, which meet spheres on their faces, edges and corners.
#include <gtest/gtest.h>

#include "lab/direct_shear_box.hpp"

namespace geodem::test {
namespace {

TEST(DirectShearBox, FramesSplitAtThePlaneAndTheUpperOneLiftedByTheGap) {
  using Vec = Dim<2>::Vec;
  World<2> w;
  w.materials = {Material{}, Material{}};
  LabBox<2> box = LabBox<2>::add_to(w, Vec(0.0, 0.0), Vec(1.0, 0.5), 1);
  w.resolve_pair_laws();
  const ShearFrames f = split_shear_box(w, box, 0.25, 0.2, 0.01);
  ASSERT_TRUE(shear_box_split(w));
  EXPECT_EQ(w.walls[box.lo[0]].end, Vec(0.0, 0.25));     // lower frame, left side
  EXPECT_EQ(w.walls[box.hi[0]].end, Vec(1.0, 0.25));     // lower frame, right side
  EXPECT_EQ(w.walls[f.upper[0]].point, Vec(0.0, 0.26));  // upper frame, left side
  EXPECT_EQ(w.walls[f.upper[1]].point, Vec(1.0, 0.26));
  EXPECT_EQ(w.walls[f.upper[2]].point, Vec(-0.2, 0.26));  // upper lip
  EXPECT_EQ(w.walls[f.lower[2]].end, Vec(1.2, 0.25));     // lower lip
  EXPECT_DOUBLE_EQ(w.walls[box.hi[1]].area, 1.0);         // the plate's stress over the length
  // Forces the grains exert: 3 N against the upper frame's motion, 3 N along +x on the lower.
  w.walls[f.upper[0]].force = Vec(-3.0, 0.0);
  w.walls[f.lower[1]].force = Vec(2.0, 0.0);
  w.walls[f.lower[2]].force = Vec(1.0, 0.0);
  EXPECT_DOUBLE_EQ(shear_box_force(w, box, f), 3.0);
  drive_upper_frame(w, f, 0.5);
  for (std::size_t k = 0; k < f.count; ++k) {
    EXPECT_EQ(w.walls[f.upper[k]].velocity, Vec(0.5, 0.0));
    EXPECT_EQ(w.walls[f.lower[k]].velocity, Vec(0.0, 0.0));
  }
}

// A rectangle wall (3D): the closest point clamped to both edges, so a sphere meets its face,
// its edges and its corners; the edge through `end` left to the next wall when not owned.
TEST(DirectShearBox, RectangleWallMeetsSpheresOnItsFaceEdgesAndCorners) {
  using Vec = Dim<3>::Vec;
  Wall<3> r;
  r.kind = WallKind::kRectangle;
  r.point = Vec(0.0, 0.0, 0.0), r.end = Vec(0.0, 0.0, 1.0), r.across = Vec(2.0, 0.0, 0.0);
  Vec q;
  ASSERT_TRUE(wall_closest(r, Vec(1.0, 0.3, 0.5), q));
  EXPECT_EQ(q, Vec(1.0, 0.0, 0.5));  // the face
  ASSERT_TRUE(wall_closest(r, Vec(-1.0, -0.2, 0.5), q));
  EXPECT_EQ(q, Vec(0.0, 0.0, 0.5));  // an edge
  ASSERT_TRUE(wall_closest(r, Vec(3.0, 0.1, -2.0), q));
  EXPECT_EQ(q, Vec(2.0, 0.0, 0.0));  // a corner
  Vec n;
  double delta = 0.0;
  ASSERT_TRUE(wall_overlap(r, Vec(1.0, 0.3, 0.5), 0.35, n, delta));
  EXPECT_NEAR(delta, 0.05, 1e-15);
  EXPECT_EQ(n, Vec(0.0, -1.0, 0.0));  // from the centre to the wall: two-sided
  ASSERT_TRUE(wall_overlap(r, Vec(1.0, -0.3, 0.5), 0.35, n, delta));
  EXPECT_EQ(n, Vec(0.0, 1.0, 0.0));
  EXPECT_FALSE(wall_overlap(r, Vec(1.0, 0.3, 1.4), 0.35, n, delta));  // beyond the end edge
  r.owns_end_vertex = false;
  EXPECT_FALSE(wall_closest(r, Vec(1.0, 0.1, 1.05), q));  // the end edge is not its own
  EXPECT_TRUE(wall_closest(r, Vec(1.0, 0.1, 0.95), q));
}

TEST(DirectShearBox, ThreeDimensionalFramesAreRectanglesAcrossTheBox) {
  using Vec = Dim<3>::Vec;
  World<3> w;
  w.materials = {Material{}, Material{}};
  LabBox<3> box = LabBox<3>::add_to(w, Vec(0.0, 0.0, 0.0), Vec(1.0, 0.6, 0.5), 1);
  w.resolve_pair_laws();
  const ShearFrames f = split_shear_box(w, box, 0.25, 0.2, 0.01);
  ASSERT_TRUE(shear_box_split(w));
  ASSERT_EQ(f.count, 5u);
  const auto& x_lo = w.walls[box.lo[0]];
  EXPECT_EQ(x_lo.kind, WallKind::kRectangle);
  EXPECT_EQ(x_lo.end, Vec(0.0, 0.0, 0.25));    // lower frame's left side, up to the split
  EXPECT_EQ(x_lo.across, Vec(0.0, 0.6, 0.0));  // across the box's width
  EXPECT_EQ(w.walls[f.upper[0]].point, Vec(0.0, 0.0, 0.26));   // upper left side, lifted
  EXPECT_EQ(w.walls[f.upper[2]].point, Vec(-0.2, 0.0, 0.26));  // upper lip
  EXPECT_EQ(w.walls[f.lower[2]].end, Vec(1.2, 0.0, 0.25));     // lower lip
  EXPECT_EQ(w.walls[f.upper[4]].point, Vec(0.0, 0.6, 0.26));   // upper frame's back side
  EXPECT_EQ(w.walls[f.upper[4]].across, Vec(1.0, 0.0, 0.0));   // along the box's length
  EXPECT_EQ(w.walls[box.hi[1]].end, Vec(0.0, 0.6, 0.25));      // lower frame's back side
  EXPECT_DOUBLE_EQ(w.walls[box.hi[2]].area, 0.6);              // the plate: length x width
  // The box's sizes still come from its side walls' first corners.
  EXPECT_EQ(box.size(w), Vec(1.0, 0.6, 0.5));
  w.walls[f.upper[3]].force = Vec(-1.0, 0.0, 0.0);  // friction on the upper front side
  w.walls[f.upper[1]].force = Vec(-2.0, 0.0, 0.0);
  w.walls[f.lower[4]].force = Vec(3.0, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(shear_box_force(w, box, f), 3.0);
  drive_upper_frame(w, f, 0.5);
  for (std::size_t k = 0; k < f.count; ++k) {
    EXPECT_EQ(w.walls[f.upper[k]].velocity, Vec(0.5, 0.0, 0.0));
    EXPECT_EQ(w.walls[f.lower[k]].velocity, Vec(0.0, 0.0, 0.0));
  }
}

}  // namespace
}  // namespace geodem::test
