// Grain-spar element contacts: a grain (free or clump member) against an element
// seen as a capsule of radius half_thickness around its axis. The contact force acts
// at the closest point of the axis, at parameter t; the element passes it to its nodes
// with the linear weights (1 - t) and t (their sum is the force and their moment about
// any point is the force's), and the grain takes the opposite force. Normal and
// tangential springs, Coulomb friction tan(delta), from the pair law of the grain's
// material and the element's. The tangential spring follows the contact point from an
// element to the next (structures/spar_geometry.hpp says which element owns a point).
#pragma once

#include "world/world.hpp"

namespace geodem {

// Adds the contact forces to grains and spar nodes (node forces are reset here).
template <int D>
void compute_spar_contacts(World<D>& world);

}  // namespace geodem
