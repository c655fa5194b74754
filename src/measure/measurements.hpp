// Measurements of the assembly, read by recorders and lab tests.
#pragma once

#include "core/world.hpp"

namespace geodem {

template <int D>
struct Box {
  typename Dim<D>::Vec lo, hi;
  double volume() const { return (hi - lo).prod(); }
};

// Translational + rotational kinetic energy of the free grains (J, or J/m in 2D).
// Velocities are the half-step ones of the leapfrog scheme.
template <int D>
double kinetic_energy(const World<D>& world);

// Potential energy of the free grains in the gravity field (zero at the origin).
template <int D>
double gravity_energy(const World<D>& world);

// Mean resultant force on the free grains (contacts + gravity) over the mean contact
// force; needs world.stats from a measuring step. NaN when there is no contact.
template <int D>
double unbalanced_force_ratio(const World<D>& world);

// Love-Weber average stress of the assembly over `volume`, compression positive:
// sigma = 1/V sum_c l_c (x) f_c (symmetric part), from a measuring step.
template <int D>
typename Dim<D>::Tensor average_stress(const World<D>& world, double volume);

// Volume (area in 2D) of solid inside the box, partial grains counted exactly
// (2D) or by Gauss quadrature over slices (3D, relative error below 1e-6).
template <int D>
double solid_volume_in_box(const World<D>& world, const Box<D>& box);

template <int D>
double porosity_in_box(const World<D>& world, const Box<D>& box) {
  return 1.0 - solid_volume_in_box(world, box) / box.volume();
}

// Mean number of grain-grain contacts per grain, 2 Nc / N, from a measuring step.
template <int D>
double coordination_number(const World<D>& world);

// Exact area of the disc (centre c, radius r) inside the rectangle [lo, hi].
double disc_rectangle_area(double cx, double cy, double r, double x0, double y0, double x1,
                           double y1);

}  // namespace geodem
