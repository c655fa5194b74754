// Measurements of the assembly, read by recorders and lab tests.
#pragma once

#include <array>

#include "world/world.hpp"

namespace geodem {

template <int D>
struct Box {
  typename Dim<D>::Vec lo, hi;
  double volume() const { return (hi - lo).prod(); }
};

// "Bodies" below are the grains that are not clump members, and the clumps.

// Translational + rotational kinetic energy of the bodies (J, or J/m in 2D).
// Velocities are the half-step ones of the leapfrog scheme.
template <int D>
double kinetic_energy(const World<D>& world);

// Potential energy of the bodies in the gravity field (zero at the origin).
template <int D>
double gravity_energy(const World<D>& world);

// Total weight of the bodies that are not fixed (N, or N/m in 2D).
template <int D>
double body_weight(const World<D>& world);

// Volume (area in 2D) of all grains, a clump's overlapping members counted once.
template <int D>
double solid_volume(const World<D>& world);

// Number of cohesive bonds still intact.
template <int D>
std::size_t intact_bonds(const World<D>& world);

// Number of bonds broken since the start (world.broken_bonds; in a decomposed world the sum of
// the ranks' counts, each bond counted by the rank that owns its row's grain).
template <int D>
std::uint64_t broken_bond_count(const World<D>& world);

// The radius of the grain with this id (0 when there is none; in a decomposed world its
// owner's, on every rank).
template <int D>
double radius_of_grain(const World<D>& world, std::uint32_t id);

// Number of bodies (free grains and clumps; fixed grains included); in a decomposed world
// (docs/parallel.md) the whole domain's, every rank's own grains and clumps counted.
template <int D>
std::size_t body_count(const World<D>& world) {
  const auto& P = world.particles;
  if (world.domain) {
    std::vector<ExactSum> n(1);
    for (auto f : P.flags) n[0].add((f & (kGhost | kClumpMember)) ? 0.0 : 1.0);
    n[0].add(static_cast<double>(world.clumps.owned()));
    world.domain->sum(n);
    return static_cast<std::size_t>(n[0].value());
  }
  std::size_t members = 0;
  for (auto c : P.clump) members += c != kNoClump;
  return P.size() - members + world.clumps.size();
}

// Numbers of grains (clump members included) and of clumps; in a decomposed world the whole
// domain's.
template <int D>
std::array<std::size_t, 2> grain_and_clump_counts(const World<D>& world) {
  const auto& P = world.particles;
  if (!world.domain) return {P.size(), world.clumps.size()};
  std::vector<ExactSum> n(2);
  for (auto f : P.flags) n[0].add((f & kGhost) ? 0.0 : 1.0);
  n[1].add(static_cast<double>(world.clumps.owned()));
  world.domain->sum(n);
  return {static_cast<std::size_t>(n[0].value()), static_cast<std::size_t>(n[1].value())};
}

// Mean resultant force on the bodies (contacts + gravity) over the mean contact
// force; needs world.stats from a measuring step. NaN when there is no contact.
template <int D>
double unbalanced_force_ratio(const World<D>& world);

// Love-Weber average stress of the assembly over `volume`, compression positive:
// sigma = 1/V sum_c l_c (x) f_c (symmetric part), from a measuring step.
template <int D>
typename Dim<D>::Tensor average_stress(const World<D>& world, double volume);

// The average stress of a periodic cell, compression positive, from any step: the contacts'
// sum of d (x) f (world.cell_fabric, clump members' centres replaced by their clump's, as
// integrate_clumps does for the fabric stress) over the cell's volume, symmetric part. In a
// decomposed cell the sum is the whole domain's, taken exactly over the ranks.
template <int D>
typename Dim<D>::Tensor cell_stress(const World<D>& world);

// Volume (area in 2D) of solid inside the box, partial grains counted exactly
// (2D) or by Gauss quadrature over slices (3D, relative error below 1e-6). Clump
// members are counted as separate grains: overlaps between them count twice.
template <int D>
double solid_volume_in_box(const World<D>& world, const Box<D>& box);

template <int D>
double porosity_in_box(const World<D>& world, const Box<D>& box) {
  return 1.0 - solid_volume_in_box(world, box) / box.volume();
}

// Mean number of grain-grain contacts per body, 2 Nc / N_bodies, from a measuring step
// (two clumps touching through two pairs of members count two contacts).
template <int D>
double coordination_number(const World<D>& world);

// Exact area of the disc (centre c, radius r) inside the rectangle [lo, hi].
double disc_rectangle_area(double cx, double cy, double r, double x0, double y0, double x1,
                           double y1);

}  // namespace geodem
