// The direct shear box's frames (lab/direct_shear_box.hpp): the side walls split at the
// split plane, the upper frame's sides and lip lifted by the gap, the lips reaching `travel`
// past the sides, and the frames' shear force the mean of the two frames' x-forces.
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
  for (std::size_t i : f.upper) EXPECT_EQ(w.walls[i].velocity, Vec(0.5, 0.0));
  for (std::size_t i : f.lower) EXPECT_EQ(w.walls[i].velocity, Vec(0.0, 0.0));
}

}  // namespace
}  // namespace geodem::test
