// The direct shear box (2D, docs/element_tests.md): the prepared sample's box of four plane
// walls becomes a box of two frames split at mid-height. The side walls become the lower
// frame's segments, and the upper frame's side segments are added above them; each frame has
// a lip along the split plane that keeps the other frame's grains from leaving through the
// gap that opens as the upper frame slides along +x. The bottom wall stays; the top wall is
// the loading plate, held at the normal stress by a servo.
#pragma once

#include <array>
#include <cstddef>

#include "walls/lab_box.hpp"
#include "world/world.hpp"
#include "world/world_editing.hpp"

namespace geodem {

// Wall indices: the lower frame's sides are the box's x walls; the walls added after the
// box's four are the upper frame's left and right sides and lip, then the lower frame's lip.
struct ShearFrames {
  std::array<std::size_t, 3> upper{4, 5, 6}, lower{0, 1, 7};
};

inline ShearFrames shear_frames(const LabBox<2>& box) {
  return {{4, 5, 6}, {box.lo[0], box.hi[0], 7}};
}

inline bool shear_box_split(const World<2>& w) {
  return w.walls.size() == 8;
}

// Splits the box's sides at height `split`; the lips reach `travel` past the sides. With a
// `gap`, the upper frame (its sides and lip) starts that much above the split plane, as a
// laboratory box's upper frame is lifted off the lower one: its corners then ride above the
// lower frame's grains instead of pushing the top ones along.
inline ShearFrames split_shear_box(World<2>& w, const LabBox<2>& box, double split, double travel,
                                   double gap = 0.0) {
  using Vec = Dim<2>::Vec;
  const ShearFrames f = shear_frames(box);
  const double length = box.size(w).x();
  const double top = w.walls[box.hi[1]].point.y() + 0.5 * box.size(w).y();
  const auto segment = [&](std::size_t index, const char* name, Vec a, Vec b) {
    Wall<2> wall = w.walls[box.lo[0]];
    wall.name = name;
    wall.kind = WallKind::kSegment;
    wall.point = a, wall.end = b, wall.normal = Vec::Zero(), wall.velocity = Vec::Zero();
    wall.area = 0.0;
    if (index < w.walls.size())
      w.walls[index] = wall;
    else
      add_wall(w, wall);
  };
  segment(box.lo[0], "lower_left", Vec(0.0, 0.0), Vec(0.0, split));
  segment(box.hi[0], "lower_right", Vec(length, 0.0), Vec(length, split));
  const double upper = split + gap;
  segment(4, "upper_left", Vec(0.0, upper), Vec(0.0, top));
  segment(5, "upper_right", Vec(length, upper), Vec(length, top));
  segment(6, "upper_lip", Vec(-travel, upper), Vec(0.0, upper));
  segment(7, "lower_lip", Vec(length, split), Vec(length + travel, split));
  w.walls[6].owns_end_vertex = false;  // the upper frame's corner belongs to its side
  w.walls[box.hi[0]].owns_end_vertex = false;
  w.walls[box.hi[1]].area = length;  // the plate's stress
  w.rebuild_needed = true;
  return f;
}

// The upper frame slides at `velocity` along +x (0 stops it).
inline void drive_upper_frame(World<2>& w, const ShearFrames& f, double velocity) {
  for (std::size_t i : f.upper) w.walls[i].velocity = Dim<2>::Vec(velocity, 0.0);
}

// The shear force on the split plane (N per metre): the mean of what the grains push on the
// lower frame along +x and on the upper frame against its motion (equal at rest), the bottom
// and plate counted with their frames (they are smooth unless walls.friction_deg is set).
inline double shear_box_force(const World<2>& w, const LabBox<2>& box, const ShearFrames& f) {
  double upper = -w.walls[box.hi[1]].force.x(), lower = w.walls[box.lo[1]].force.x();
  for (std::size_t i : f.upper) upper -= w.walls[i].force.x();
  for (std::size_t i : f.lower) lower += w.walls[i].force.x();
  return 0.5 * (upper + lower);
}

}  // namespace geodem
