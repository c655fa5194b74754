// Geometry of a geosynthetic anchorage (2D, x horizontal towards the anchor, y up) and
// the analytic slippage estimate of its capacity (docs/lab_tests.md, "Pull-out").
// The sheet leaves the front wall (x = 0) at the run-out level y0 and runs horizontally
// for runout_length; an L-shaped anchor then goes straight down the front side of a
// trench (width trench_width behind it) to trench_depth; a V-shaped anchor goes down
// the front flank of a V trench (top width trench_width) to its apex. The trench's front
// edge, which the sheet turns round, may be rounded (edge_radius).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "lab/pullout_settings.hpp"

namespace geodem {

using Point2 = Eigen::Vector2d;

// Corners of the sheet from the pulled end (outside the box, at x = -free_length) to
// the anchored end.
std::vector<Point2> sheet_corners(const AnchorGeometry& g, double y0);

// Nodes along the corners: each straight part cut into equal elements no longer than
// element_length, with a node on every corner.
std::vector<Point2> sheet_nodes(const std::vector<Point2>& corners, double element_length);

// The bend of an L or V (none for a run-out): where the run-out turns down the trench's
// front side, round the trench's front edge when g.edge_radius > 0. The arc of that radius
// touches the run-out at `start` and the trench side at `end`; `middle` is the arc's
// midpoint (the corner itself when the edge is sharp).
struct SheetBend {
  Point2 corner, centre, start, end, middle;
  double radius = 0.0;
  double turn = 0.0;  // rad, the angle the sheet turns through (pi / 2 for an L)
};
std::optional<SheetBend> sheet_bend(const AnchorGeometry& g, double y0);

// The sheet's nodes: sheet_nodes along the corners, with the bend rounded to an arc of
// equal elements (each no longer than element_length) when the edge is rounded.
std::vector<Point2> sheet_path_nodes(const AnchorGeometry& g, double y0, double element_length);

// True when a disc (centre x, radius r) overlaps the excavated trench below y0, the
// rounded trench edge included (the foundation outside the arc is cut away).
bool overlaps_trench(const AnchorGeometry& g, double y0, const Point2& x, double r);

// Resistance of an anchorage whose every face has the shear strength
// tau = a + sigma_n tan(phi) (docs/lab_tests.md, "Design methods"); both faces of the
// sheet resist, the soil around it is at rest (at-rest stresses).
// - Horizontal run-out of length L under sigma_v0 = gamma cover + q:
//     F1 = 2 L a + 2 L sigma_v0 tan(phi),
//   or, given the load on the run-out (the weight of the soil above it plus q L, which
//   a cover that thins towards a free front makes smaller than L sigma_v0),
//     F1 = 2 L a + 2 tan(phi) x load.
// - Sloping part of length l at angle beta below the horizontal, under the at-rest
//   stresses sigma_v = sigma_v0 + gamma z, sigma_h = K sigma_v: the normal stress is
//   sigma_n = sigma_v (cos^2 beta + K sin^2 beta), so
//     F2 = 2 l a + 2 tan(phi) (cos^2 beta + K sin^2 beta) (sigma_v0 l + gamma l^2 sin(beta) / 2)
//   (beta = 90 deg for the L: F2 = 2 D a + 2 tan(phi) K (sigma_v0 D + gamma D^2 / 2)).
// - With `capstan`, the bend of angle beta between them multiplies the tension carried
//   round it by exp(beta tan(phi)): T = F1 + exp(beta tan(phi)) F2; without, T = F1 + F2.
struct AnchorEstimate {
  double tension = 0.0;  // N/m
  double runout = 0.0;   // F1
  double trench = 0.0;   // F2 (before the capstan factor)
  double capstan = 1.0;  // exp(beta tan(phi)), or 1
  double sigma_v0 = 0.0;
  double K = 0.0;
  // The normal forces the estimate assumes on both faces: 2 x load on the run-out, and
  // F2's 2 (cos^2 beta + K sin^2 beta) (sigma_v0 l + gamma l^2 sin(beta) / 2) beyond the bend.
  double runout_normal = 0.0, trench_normal = 0.0;
};
AnchorEstimate anchor_resistance(const AnchorGeometry& g, double unit_weight, double surcharge,
                                 double tan_phi, double adhesion, double K, double runout_load,
                                 bool capstan);

// Slippage at the interface (Villard and Chareyre's first hypothesis, cohesive soils):
// the sheet slides out against soil at rest, with the macroscopic interface friction
// delta and adhesion a, and wraps the bend as a rope round a fixed drum (capstan).
using SlipEstimate = AnchorEstimate;
SlipEstimate slip_estimate(const AnchorGeometry& g, double unit_weight, double surcharge,
                           double tan_delta, double K, double runout_load = -1.0,
                           double adhesion = 0.0);

// Deformation of the anchoring soil mass (the second hypothesis, frictional soils): the
// soil next to the sheet moves with it, so the failure surfaces run through the soil on
// both faces, with the soil's cohesion c and friction phi; the soil that wraps the bend
// moves with the sheet and rounds it, so the bend is no fixed drum and adds no capstan
// factor. Governs where it is below the slippage estimate: a frictional soil with phi not
// far above delta and a bend whose capstan factor is large.
AnchorEstimate soil_estimate(const AnchorGeometry& g, double unit_weight, double surcharge,
                             double tan_phi, double cohesion, double K, double runout_load = -1.0);

}  // namespace geodem
