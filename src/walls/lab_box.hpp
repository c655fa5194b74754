// The rigid box of a lab test: one pair of plane walls per axis, lo (normal +e_k)
// and hi (normal -e_k). Stresses come from the wall forces over the current face
// areas, strains from the wall positions; both compression positive.
//
// Or, without walls, a periodic cell of the same size (world/periodic_cell.hpp), kept
// rectangular: its size is the diagonal of h, its stresses the cell's average stress.
#pragma once

#include <array>
#include <string>

#include "measure/measurements.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
struct LabBox {
  using Vec = typename Dim<D>::Vec;
  std::array<std::size_t, D> lo{}, hi{};  // wall indices
  Vec initial_size = Vec::Zero();
  bool periodic = false;

  // A periodic cell [0, size] in place of walls.
  static LabBox periodic_cell(World<D>& w, const Vec& size) {
    LabBox box;
    box.periodic = true;
    box.initial_size = size;
    w.cell.periodic = true;
    w.cell.h = size.asDiagonal();
    w.cell.vel_grad.setZero();
    return box;
  }

  // Adds the 2D walls of the box [a, b] with the given material; records the size.
  static LabBox add_to(World<D>& w, const Vec& a, const Vec& b, std::uint16_t material) {
    static const char* names[] = {"x", "y", "z"};
    LabBox box;
    for (int k = 0; k < D; ++k) {
      for (int side = 0; side < 2; ++side) {
        Wall<D> wall;
        wall.name = std::string(names[k]) + (side == 0 ? "_lo" : "_hi");
        wall.point = side == 0 ? a : b;
        wall.normal = Vec::Zero();
        wall.normal[k] = side == 0 ? 1.0 : -1.0;
        wall.material = material;
        (side == 0 ? box.lo : box.hi)[k] = w.walls.size();
        w.walls.push_back(wall);
      }
    }
    box.initial_size = b - a;
    return box;
  }

  Vec size(const World<D>& w) const {
    if (periodic) return w.cell.h.diagonal();
    Vec s;
    for (int k = 0; k < D; ++k) s[k] = w.walls[hi[k]].point[k] - w.walls[lo[k]].point[k];
    return s;
  }
  // Area of the faces normal to axis k (a length per metre of thickness in 2D).
  double area(const World<D>& w, int k) const {
    const Vec s = size(w);
    double a = 1.0;
    for (int j = 0; j < D; ++j)
      if (j != k) a *= s[j];
    return a;
  }
  double volume(const World<D>& w) const { return size(w).prod(); }
  // Mean normal stress on the two faces normal to axis k.
  double stress(const World<D>& w, int k) const {
    if (periodic) return cell_stress(w)(k, k);
    const auto nf = [&](std::size_t i) { return -w.walls[i].force.dot(w.walls[i].normal); };
    return 0.5 * (nf(lo[k]) + nf(hi[k])) / area(w, k);
  }
  double mean_stress(const World<D>& w) const {
    if (periodic) return cell_stress(w).trace() / D;
    double s = 0.0;
    for (int k = 0; k < D; ++k) s += stress(w, k);
    return s / D;
  }
  // Engineering strain along k from the size at `reference`, compression positive.
  double strain(const World<D>& w, int k, const Vec& reference) const {
    return (reference[k] - size(w)[k]) / reference[k];
  }
  // Volumetric strain 1 - V/V_ref, positive in contraction.
  double volumetric_strain(const World<D>& w, const Vec& reference) const {
    return 1.0 - volume(w) / reference.prod();
  }
};

}  // namespace geodem
