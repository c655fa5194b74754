// The spar chains' own dynamics: element tensions (tension only), bending moments at
// interior nodes (2D), and the leapfrog update of the nodes with gravity and local
// damping, in the same step as the grains.
#pragma once

#include "world/world.hpp"

namespace geodem {

// An element's axial force (N/m in 2D, N in 3D; positive in tension): J x strain when
// stretched, nothing when slack, and a push of J x (thickness - length) / rest length once
// its nodes come closer than the sheet's thickness.
double axial_force(double J, double length, double rest_length, double thickness);

// Stage "structures": adds the element tensions and bending forces to the nodes'
// forces (already holding the grain contacts) and stores each element's tension.
template <int D>
void spar_element_forces(World<D>& world);

// Advances the nodes by one step; returns the largest node speed squared.
template <int D>
double integrate_spar_nodes(World<D>& world);

// Smallest m / k over the nodes (k: the diagonal stiffness of the elements, the
// bending springs and the grain contacts on the node), for the critical time step.
template <int D>
double spar_min_mass_over_stiffness(const World<D>& world);

// Largest node displacement since the neighbour list was built.
template <int D>
double spar_max_displacement(const World<D>& world);

}  // namespace geodem
