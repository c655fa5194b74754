// Rigid boundaries: infinite planes (any orientation, one-sided), in 2D segments
// (two-sided, chained into polylines) and in 3D rectangles (two-sided: a segment swept
// along a second edge, the frames of a shear box). Walls move with a prescribed velocity
// or under a controller; the force the grains exert on each wall is summed every step.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "base/dim.hpp"

namespace geodem {

enum class WallKind : std::uint8_t { kPlane, kSegment, kRectangle };

template <int D>
struct Wall {
  using Vec = typename Dim<D>::Vec;
  std::string name;
  WallKind kind = WallKind::kPlane;
  Vec point = Vec::Zero();   // plane: a point on it; segment: first end
  Vec normal = Vec::Zero();  // plane: unit normal pointing into the grains' side
  Vec end = Vec::Zero();     // segment: second end; rectangle: the first edge's other end
  Vec across = Vec::Zero();  // rectangle: its second edge (from point, normal to the first)
  Vec velocity = Vec::Zero();
  std::uint16_t material = 0;
  // Segments of one polyline share vertices; a grain touching a shared vertex
  // is counted by one segment only (the one that starts there). A rectangle that does not
  // own its end edge (the side through `end`) leaves it to the rectangle that meets it there.
  bool owns_end_vertex = true;
  double area = 0.0;  // for the stress on the wall (m^2 in 3D, m in 2D); 0: unknown

  // Results of the current step.
  Vec force = Vec::Zero();  // force exerted by the grains on the wall
  double stiffness = 0.0;   // sum of its contacts' normal stiffnesses (for servo control)
  double dashpot =
      0.0;  // sum of their normal dashpot coefficients (N s/m; World::tally_wall_dashpots)
  Vec displacement = Vec::Zero();  // since the neighbour list was built

  double normal_stress() const { return area > 0.0 ? -force.dot(normal) / area : 0.0; }
};

// Closest point of a wall to x, with the gap (distance from x to the wall,
// signed for planes; a rectangle's point is clamped to both of its edges). Returns false when the
// segment's vertex-owner rule excludes it (only when `apply_owner_rule`: the force loop applies it,
// the list does not).
template <int D>
inline bool wall_closest(const Wall<D>& w, const typename Dim<D>::Vec& x,
                         typename Dim<D>::Vec& closest, bool apply_owner_rule = true) {
  if (w.kind == WallKind::kPlane) {
    closest = x - (x - w.point).dot(w.normal) * w.normal;
    return true;
  }
  const typename Dim<D>::Vec seg = w.end - w.point;
  const double len2 = seg.squaredNorm();
  double t = len2 > 0.0 ? (x - w.point).dot(seg) / len2 : 0.0;
  if (t >= 1.0) {
    if (apply_owner_rule && !w.owns_end_vertex) return false;
    t = 1.0;
  }
  if (t < 0.0) t = 0.0;
  closest = w.point + t * seg;
  if (w.kind == WallKind::kRectangle) {
    const double wide2 = w.across.squaredNorm();
    const double u = wide2 > 0.0 ? (x - w.point).dot(w.across) / wide2 : 0.0;
    closest += std::clamp(u, 0.0, 1.0) * w.across;
  }
  return true;
}

// A sphere (centre x, radius r) against a wall as the force stage meets it: the unit normal
// n from the centre to the wall and the overlap delta > 0; false when they do not touch, when
// the vertex-owner rule gives the contact to the next segment, or when the centre lies on a
// segment or rectangle (no normal).
template <int D>
inline bool wall_overlap(const Wall<D>& w, const typename Dim<D>::Vec& x, double r,
                         typename Dim<D>::Vec& n, double& delta) {
  using Vec = typename Dim<D>::Vec;
  Vec q;
  if (!wall_closest(w, x, q)) return false;
  const Vec d = q - x;
  const bool plane = w.kind == WallKind::kPlane;
  const double gap = plane ? (x - w.point).dot(w.normal) : d.norm();
  delta = r - gap;
  if (delta <= 0.0 || (!plane && gap <= 0.0)) return false;
  n = plane ? Vec(-w.normal) : Vec(d / gap);
  return true;
}

}  // namespace geodem
