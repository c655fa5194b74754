// The periodic cell: a parallelepiped that repeats in every direction, deformed
// homogeneously (yade's Cell, LAMMPS's fix deform). Its edge vectors are the columns of h;
// the velocity gradient L deforms it, dh/dt = L h, and carries every grain with the affine
// field u(x) = L x.
//
// Grains store their velocity relative to that field (the fluctuation): positions advance by
// (v + L x) dt, the relative velocity of two grains' centres is v_j - v_i + L d with d the
// branch vector, and damping and kinetic energy see the fluctuation only. A listed pair
// carries the image of its partner (integers m: the partner is seen at x_j + h m), found by
// the neighbour search, so that a contact across the boundary keeps its history like any
// other.
#pragma once

#include <cmath>

#include "base/dim.hpp"
#include "contacts/neighbour_list.hpp"

namespace geodem {

template <int D>
struct PeriodicCell {
  using Vec = typename Dim<D>::Vec;
  using Tensor = typename Dim<D>::Tensor;
  bool periodic = false;
  Tensor h = Tensor::Identity();           // edge vectors as columns (m)
  Tensor vel_grad = Tensor::Zero();        // L (1/s)
  Tensor h_at_build = Tensor::Identity();  // h when the neighbour list was built

  double volume() const { return std::abs(h.determinant()); }
  // The offset of image m: the sum of m_k times edge k, in a fixed order.
  Vec shift(const CellImage& c) const {
    Vec s = Vec::Zero();
    for (int k = 0; k < D; ++k)
      if (c.m[k] != 0) s += static_cast<double>(c.m[k]) * h.col(k);
    return s;
  }
  double reach_at_build = 0.0;  // largest diameter plus skin at the last build
  // The strain since the list was built: |F - I| (Frobenius, not less than the largest
  // stretch) with F = h h_build^-1. Two grains a reach apart have closed by at most that
  // times the reach, beyond their own displacements from the affine motion.
  double strain_since_build() const {
    return (h * h_at_build.inverse() - Tensor::Identity()).norm();
  }
  // The cell's width across each pair of faces (the distance between the faces): edge k's
  // reach is 1 / |row k of h^-1|.
  Vec widths() const {
    const Tensor inv = h.inverse();
    Vec w;
    for (int k = 0; k < D; ++k) w[k] = 1.0 / inv.row(k).norm();
    return w;
  }
  // Advances the cell by one step of the velocity gradient.
  void deform(double dt) { h += dt * (vel_grad * h); }
};

}  // namespace geodem
