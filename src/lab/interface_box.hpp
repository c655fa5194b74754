// The interface shear box (docs/lab_tests.md, "Interface shear"): soil in a rigid box,
// loaded by a plate held at a normal stress, over a geosynthetic sheet that slides at a
// constant rate. These parts build the box in a world and read the interface stresses;
// the runner (run_interface_shear.cpp) and the verification tests use the same ones.
//
// Two bases. "rigid": the sheet is the floor of the box, a spar chain whose nodes are
// all driven: it keeps its shape, and the force the grains exert on it is the sum of its
// nodes' contact forces, which the contact stage leaves in SparChains::force (no element
// is stretched, so no element force is mixed in); it reaches past both side walls far
// enough that the soil never loses it. "soil": the sheet lies between two layers of
// soil and is pulled out through a side wall by its clamp, free to drape over the grains
// and to stretch, as in a pull-out; the shear stress on each face is the clamp's
// tension over twice the embedded length.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "base/exact_sum.hpp"
#include "world/world.hpp"

namespace geodem {

struct InterfaceBox {
  double length = 0.3;           // soil box length (m): the sheared length of the interface
  double thickness = 0.002;      // sheet thickness (m): its upper face is at y = thickness
  double element_length = 0.01;  // sheet element length (m)
  double travel = 0.05;          // how far the sheet will slide (m)
  double margin = 0.02;          // sheet length past each wall beyond the travel (m)
  double mass_per_area = 0.5;    // kg/m^2 (the base drives the nodes: only for the record)
  double stiffness_J = 1e6;      // N/m (a rigid base keeps the sheet unstretched)
  double bending = 0.0;          // N m/rad per m at each node (a sheet pulled through soil)
  std::uint16_t wall_material = 1, sheet_material = 2;
};

enum : std::size_t { kShearFloor = 0, kShearLeft = 1, kShearRight = 2 };

// The walls: a floor and the two side walls x = 0 and x = length (kShearFloor...). Under
// a rigid base the floor only catches a grain that would ever pass through the sheet.
inline void add_interface_box_walls(World<2>& w, const InterfaceBox& b) {
  using Vec = Dim<2>::Vec;
  auto plane = [&](const char* name, Vec point, Vec normal, double area) {
    Wall<2> wall;
    wall.name = name;
    wall.point = point;
    wall.normal = normal;
    wall.material = b.wall_material;
    wall.area = area;
    w.walls.push_back(wall);
  };
  plane("floor", Vec(0.0, 0.0), Vec(0.0, 1.0), b.length);
  plane("left", Vec(0.0, 0.0), Vec(1.0, 0.0), 0.0);
  plane("right", Vec(b.length, 0.0), Vec(-1.0, 0.0), 0.0);
}

// A rigid base: the sheet (chain 0) at the bottom of the box, its nodes all driven and
// still, reaching past both side walls.
inline void add_rigid_base_sheet(World<2>& w, const InterfaceBox& b) {
  using Vec = Dim<2>::Vec;
  const double x0 = -(b.travel + b.margin), x1 = b.length + b.margin;
  const auto n = static_cast<std::size_t>(std::ceil((x1 - x0) / b.element_length));
  std::vector<Vec> nodes;
  for (std::size_t i = 0; i <= n; ++i)
    nodes.emplace_back(x0 + (x1 - x0) * static_cast<double>(i) / static_cast<double>(n),
                       0.5 * b.thickness);
  w.spars.add_chain("sheet", nodes, b.stiffness_J, b.mass_per_area, b.thickness, b.sheet_material);
  for (auto& f : w.spars.flags) f = kNodeDriven;
}

// A sheet pulled through the soil (base "soil"): its axis at height y, from its clamp
// (node 0, driven, outside the box at x = -margin) through the side wall x = 0 to its free
// end at x = end inside the box.
inline void add_pulled_sheet(World<2>& w, const InterfaceBox& b, double y, double end) {
  using Vec = Dim<2>::Vec;
  const double x0 = -b.margin;
  const auto n = static_cast<std::size_t>(std::ceil((end - x0) / b.element_length));
  std::vector<Vec> nodes;
  for (std::size_t i = 0; i <= n; ++i)
    nodes.emplace_back(x0 + (end - x0) * static_cast<double>(i) / static_cast<double>(n), y);
  w.spars.add_chain("sheet", nodes, b.stiffness_J, b.mass_per_area, b.thickness, b.sheet_material,
                    b.bending);
  w.spars.flags[0] = kNodeDriven;
}

// The loading plate, a plane facing down at height y; returns its wall index.
inline std::size_t add_loading_plate(World<2>& w, const InterfaceBox& b, double y) {
  Wall<2> plate;
  plate.name = "plate";
  plate.point = Dim<2>::Vec(0.0, y);
  plate.normal = Dim<2>::Vec(0.0, -1.0);
  plate.material = b.wall_material;
  plate.area = b.length;
  w.walls.push_back(plate);
  return w.walls.size() - 1;
}

// Sets the sheet sliding along x at `velocity` (m/s; 0 stops it).
inline void drive_sheet(World<2>& w, double velocity) {
  for (auto& v : w.spars.vel) v = Dim<2>::Vec(velocity, 0.0);
}

// Stresses the grains exert on the sheet this step, over the box length: shear stress
// against the sheet's motion (+x) and normal stress, compression positive (Pa).
struct InterfaceStresses {
  double shear = 0.0, normal = 0.0;
};
inline InterfaceStresses interface_stresses(const World<2>& w, double length) {
  double fx = 0.0, fy = 0.0;
  for (const auto& f : w.spars.force) fx += f.x(), fy += f.y();
  return {-fx / length, -fy / length};
}

// Weight of the bodies (N per metre) wholly at or above height y (a clump: every member):
// what the sheet carries beyond the plate's load. A decomposed world's is every rank's own
// bodies', summed exactly over the ranks.
inline double grains_weight_above(const World<2>& w, double y) {
  const auto& P = w.particles;
  const auto& C = w.clumps;
  std::vector<char> below(C.size(), 0);
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.member(i) && P.pos[i].y() < y) below[P.clump[i]] = 1;
  auto grain = [&](std::size_t i) {
    return !P.member(i) && P.inv_mass[i] > 0.0 && P.pos[i].y() >= y ? 1.0 / P.inv_mass[i] : 0.0;
  };
  auto clump = [&](std::size_t c) {
    return C.inv_mass[c] > 0.0 && !below[c] ? 1.0 / C.inv_mass[c] : 0.0;
  };
  double m = 0.0;
  if (!w.domain) {
    for (std::size_t i = 0; i < P.size(); ++i) m += grain(i);
    for (std::size_t c = 0; c < C.size(); ++c) m += clump(c);
  } else {
    std::vector<ExactSum> sum(1);
    for (std::size_t i = 0; i < P.size(); ++i)
      if (!(P.flags[i] & kGhost)) sum[0].add(grain(i));
    for (std::size_t c = 0; c < C.owned(); ++c) sum[0].add(clump(c));
    w.domain->sum(sum);
    m = sum[0].value();
  }
  return m * w.gravity.norm();
}

// Weight of all the grains (N per metre).
inline double grains_weight(const World<2>& w) {
  return grains_weight_above(w, -std::numeric_limits<double>::infinity());
}

}  // namespace geodem
