#include "lab/anchorage.hpp"

#include <algorithm>
#include <cmath>

namespace geodem {

namespace {

// Apex and top corners of the V trench; the sheet lies on the front flank.
struct VTrench {
  Point2 front, back, apex;
};
VTrench v_trench(const AnchorGeometry& g, double y0) {
  const double x0 = g.runout_length;
  return {Point2(x0, y0), Point2(x0 + g.trench_width, y0),
          Point2(x0 + 0.5 * g.trench_width, y0 - g.trench_depth)};
}

double segment_distance(const Point2& x, const Point2& a, const Point2& b) {
  const Point2 s = b - a;
  const double t = std::clamp((x - a).dot(s) / s.squaredNorm(), 0.0, 1.0);
  return (a + t * s - x).norm();
}

double cross(const Point2& a, const Point2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace

std::vector<Point2> sheet_corners(const AnchorGeometry& g, double y0) {
  std::vector<Point2> c = {Point2(-g.free_length, y0), Point2(g.runout_length, y0)};
  if (g.shape == "L") c.emplace_back(g.runout_length, y0 - g.trench_depth);
  if (g.shape == "V") c.push_back(v_trench(g, y0).apex);
  return c;
}

std::vector<Point2> sheet_nodes(const std::vector<Point2>& corners, double element_length) {
  std::vector<Point2> nodes = {corners.front()};
  for (std::size_t k = 0; k + 1 < corners.size(); ++k) {
    const Point2 a = corners[k], b = corners[k + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / element_length - 1e-9)));
    for (int j = 1; j <= n; ++j) nodes.push_back(a + (b - a) * (static_cast<double>(j) / n));
  }
  return nodes;
}

std::optional<SheetBend> sheet_bend(const AnchorGeometry& g, double y0) {
  const auto c = sheet_corners(g, y0);
  if (c.size() < 3) return std::nullopt;
  SheetBend b;
  b.corner = c[1];
  const Point2 u1 = (c[1] - c[0]).normalized(), u2 = (c[2] - c[1]).normalized();
  b.turn = std::abs(std::atan2(cross(u1, u2), u1.dot(u2)));
  b.radius = g.edge_radius;
  // The arc touches both straight parts at tan(turn / 2) x radius from the corner; its
  // centre lies a radius inside the turn (below the run-out: the sheet turns clockwise).
  const double a = b.radius * std::tan(0.5 * b.turn);
  b.start = b.corner - a * u1;
  b.end = b.corner + a * u2;
  b.centre = b.start + b.radius * Point2(u1.y(), -u1.x());
  const Point2 mid_dir = (u2 - u1).normalized();  // from the corner towards the centre
  b.middle = b.radius > 0.0 ? Point2(b.centre - b.radius * mid_dir) : b.corner;
  return b;
}

std::vector<Point2> sheet_path_nodes(const AnchorGeometry& g, double y0, double element_length) {
  auto corners = sheet_corners(g, y0);
  const auto b = sheet_bend(g, y0);
  if (!b || b->radius <= 0.0) return sheet_nodes(corners, element_length);
  // The arc's nodes, equally spaced in angle, become corners of the polyline: each arc
  // piece is then one element.
  const int n =
      std::max(1, static_cast<int>(std::ceil(b->radius * b->turn / element_length - 1e-9)));
  std::vector<Point2> path = {corners[0]};
  const Point2 r0 = b->start - b->centre;
  for (int j = 0; j <= n; ++j) {
    const double phi = -b->turn * static_cast<double>(j) / n;  // clockwise
    const double cs = std::cos(phi), sn = std::sin(phi);
    path.push_back(b->centre + Point2(cs * r0.x() - sn * r0.y(), sn * r0.x() + cs * r0.y()));
  }
  path.insert(path.end(), corners.begin() + 2, corners.end());
  return sheet_nodes(path, element_length);
}

bool overlaps_trench(const AnchorGeometry& g, double y0, const Point2& x, double r) {
  const auto b = g.edge_radius > 0.0 ? sheet_bend(g, y0) : std::nullopt;
  if (b) {
    // The rounded edge cuts the wedge between the arc and the sharp corner: a disc whose
    // centre lies within the arc's angle, seen from its centre, reaching past the arc and
    // not wholly beyond either straight part's line (the trench side's or the run-out's).
    // The angle alone is an unbounded sector: it once cut the foundation behind the trench
    // down to the arc's centre.
    const Point2 q = x - b->centre, s0 = b->start - b->centre, s1 = b->end - b->centre;
    const bool in_sector = cross(s0, q) <= 0.0 && cross(q, s1) <= 0.0;
    // (s0 and s1 point from the centre to the tangent lines, which lie a radius along them)
    const bool within_lines =
        q.dot(s0) < b->radius * (b->radius + r) && q.dot(s1) < b->radius * (b->radius + r);
    if (in_sector && within_lines && q.norm() + r > b->radius) return true;
  }
  if (g.shape == "L") {
    const Point2 lo(g.runout_length, y0 - g.trench_depth), hi(g.runout_length + g.trench_width, y0);
    const Point2 q = x.cwiseMax(lo).cwiseMin(hi);
    return (q - x).norm() < r;
  }
  if (g.shape == "V") {
    const VTrench v = v_trench(g, y0);
    // Inside the triangle (front, apex, back), or within r of one of its sides.
    const double c1 = cross(v.apex - v.front, x - v.front);
    const double c2 = cross(v.back - v.apex, x - v.apex);
    const double c3 = cross(v.front - v.back, x - v.back);
    const bool inside = (c1 >= 0 && c2 >= 0 && c3 >= 0) || (c1 <= 0 && c2 <= 0 && c3 <= 0);
    return inside || segment_distance(x, v.front, v.apex) < r ||
           segment_distance(x, v.apex, v.back) < r || segment_distance(x, v.back, v.front) < r;
  }
  return false;
}

AnchorEstimate anchor_resistance(const AnchorGeometry& g, double unit_weight, double surcharge,
                                 double tan_phi, double adhesion, double K, double runout_load,
                                 bool capstan) {
  AnchorEstimate e;
  e.K = K;
  e.sigma_v0 = unit_weight * g.cover + surcharge;
  e.runout_normal = 2.0 * (runout_load >= 0.0 ? runout_load : g.runout_length * e.sigma_v0);
  e.runout = 2.0 * adhesion * g.runout_length + tan_phi * e.runout_normal;
  if (g.shape != "runout") {
    const double half = g.shape == "V" ? 0.5 * g.trench_width : 0.0;
    const double l = std::hypot(half, g.trench_depth);
    const double sinb = g.trench_depth / l, cosb = half / l;
    const double beta = std::atan2(g.trench_depth, half);
    e.trench_normal =
        2.0 * (cosb * cosb + K * sinb * sinb) * (e.sigma_v0 * l + 0.5 * unit_weight * l * l * sinb);
    e.trench = 2.0 * adhesion * l + tan_phi * e.trench_normal;
    if (capstan) e.capstan = std::exp(beta * tan_phi);
  }
  e.tension = e.runout + e.capstan * e.trench;
  return e;
}

SlipEstimate slip_estimate(const AnchorGeometry& g, double unit_weight, double surcharge,
                           double tan_delta, double K, double runout_load, double adhesion) {
  return anchor_resistance(g, unit_weight, surcharge, tan_delta, adhesion, K, runout_load, true);
}

AnchorEstimate soil_estimate(const AnchorGeometry& g, double unit_weight, double surcharge,
                             double tan_phi, double cohesion, double K, double runout_load) {
  return anchor_resistance(g, unit_weight, surcharge, tan_phi, cohesion, K, runout_load, false);
}

}  // namespace geodem
