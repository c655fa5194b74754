// The direct shear box (docs/element_tests.md): the prepared sample's box of plane walls
// becomes a box of two frames split at mid-height. The side walls become the lower frame's
// sides (segments in 2D, rectangles in 3D), and the upper frame's sides are added above them;
// each frame has a lip along the split plane that keeps the other frame's grains from leaving
// through the gap that opens as the upper frame slides along +x. The bottom wall stays; the
// top wall is the loading plate, held at the normal stress by a servo. In 3D the frames also
// have sides normal to y, the upper ones sliding with their frame.
#pragma once

#include <array>
#include <cstddef>

#include "walls/lab_box.hpp"
#include "world/world.hpp"
#include "world/world_editing.hpp"

namespace geodem {

// Wall indices: the lower frame's sides are the box's side walls; the walls added after the
// box's 2D are the upper frame's x sides and lip, the lower frame's lip, then (3D) the upper
// frame's y sides. `count` of each array is used.
struct ShearFrames {
  std::array<std::size_t, 5> upper{}, lower{};
  std::size_t count = 3;
};

template <int D>
ShearFrames shear_frames(const LabBox<D>& box) {
  constexpr std::size_t n = 2 * D;
  if constexpr (D == 2) return {{n, n + 1, n + 2}, {box.lo[0], box.hi[0], n + 3}, 3};
  return {{n, n + 1, n + 2, n + 4, n + 5}, {box.lo[0], box.hi[0], n + 3, box.lo[1], box.hi[1]}, 5};
}

template <int D>
bool shear_box_split(const World<D>& w) {
  return w.walls.size() == (D == 2 ? 8u : 12u);
}

// Splits the box's sides at height `split`; the lips reach `travel` past the sides. With a
// `gap`, the upper frame (its sides and lip) starts that much above the split plane, as a
// laboratory box's upper frame is lifted off the lower one: its corners then ride above the
// lower frame's grains instead of pushing the top ones along.
template <int D>
ShearFrames split_shear_box(World<D>& w, const LabBox<D>& box, double split, double travel,
                            double gap = 0.0) {
  using Vec = typename Dim<D>::Vec;
  constexpr int v = D - 1;  // the vertical axis
  const ShearFrames f = shear_frames(box);
  const Vec size = box.size(w);
  const double length = size.x(), width = D == 3 ? size[1] : 0.0;
  const double top = w.walls[box.hi[v]].point[v] + 0.5 * size[v];
  const auto at = [](double x, double y, double z) {
    Vec p;
    p[0] = x;
    p[D - 1] = z;
    if constexpr (D == 3) p[1] = y;
    return p;
  };
  // A side from a to b (2D: a segment; 3D: that edge swept across the box's width, or
  // along its length for the sides normal to y).
  const auto side = [&](std::size_t index, const char* name, Vec a, Vec b, Vec across) {
    Wall<D> wall = w.walls[box.lo[0]];
    wall.name = name;
    wall.kind = D == 2 ? WallKind::kSegment : WallKind::kRectangle;
    wall.point = a, wall.end = b, wall.across = across;
    wall.normal = Vec::Zero(), wall.velocity = Vec::Zero();
    wall.area = 0.0;
    if (index < w.walls.size())
      w.walls[index] = wall;
    else
      add_wall(w, wall);
  };
  const Vec across_y = D == 3 ? at(0.0, width, 0.0) : Vec::Zero();
  const Vec along_x = at(length, 0.0, 0.0);
  const double upper = split + gap;
  side(box.lo[0], "lower_left", at(0.0, 0.0, 0.0), at(0.0, 0.0, split), across_y);
  side(box.hi[0], "lower_right", at(length, 0.0, 0.0), at(length, 0.0, split), across_y);
  side(f.upper[0], "upper_left", at(0.0, 0.0, upper), at(0.0, 0.0, top), across_y);
  side(f.upper[1], "upper_right", at(length, 0.0, upper), at(length, 0.0, top), across_y);
  side(f.upper[2], "upper_lip", at(-travel, 0.0, upper), at(0.0, 0.0, upper), across_y);
  side(f.lower[2], "lower_lip", at(length, 0.0, split), at(length + travel, 0.0, split), across_y);
  if constexpr (D == 3) {
    side(box.lo[1], "lower_front", at(0.0, 0.0, 0.0), at(0.0, 0.0, split), along_x);
    side(box.hi[1], "lower_back", at(0.0, width, 0.0), at(0.0, width, split), along_x);
    side(f.upper[3], "upper_front", at(0.0, 0.0, upper), at(0.0, 0.0, top), along_x);
    side(f.upper[4], "upper_back", at(0.0, width, upper), at(0.0, width, top), along_x);
  }
  w.walls[f.upper[2]].owns_end_vertex = false;  // the upper frame's corner belongs to its side
  w.walls[box.hi[0]].owns_end_vertex = false;
  w.walls[box.hi[v]].area = D == 3 ? length * width : length;  // the plate's stress
  w.rebuild_needed = true;
  return f;
}

// The upper frame slides at `velocity` along +x (0 stops it).
template <int D>
void drive_upper_frame(World<D>& w, const ShearFrames& f, double velocity) {
  typename Dim<D>::Vec v = Dim<D>::Vec::Zero();
  v[0] = velocity;
  for (std::size_t k = 0; k < f.count; ++k) w.walls[f.upper[k]].velocity = v;
}

// The shear force on the split plane (N, or N per metre in 2D): the mean of what the grains
// push on the lower frame along +x and on the upper frame against its motion (equal at rest),
// the bottom and plate counted with their frames (they are smooth unless walls.friction_deg is
// set).
template <int D>
double shear_box_force(const World<D>& w, const LabBox<D>& box, const ShearFrames& f) {
  double upper = -w.walls[box.hi[D - 1]].force.x(), lower = w.walls[box.lo[D - 1]].force.x();
  for (std::size_t k = 0; k < f.count; ++k) {
    upper -= w.walls[f.upper[k]].force.x();
    lower += w.walls[f.lower[k]].force.x();
  }
  return 0.5 * (upper + lower);
}

}  // namespace geodem
