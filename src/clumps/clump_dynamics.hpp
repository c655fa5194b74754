// The clump part of the integration stage: members' forces summed onto their clumps,
// rigid-body leapfrog of each clump, members placed back on their clump.
#pragma once

#include "world/world.hpp"

namespace geodem {

// Integrates every clump over world.dt; returns the largest squared member velocity
// (for the neighbour list's displacement bound). No-op without clumps.
template <int D>
double integrate_clumps(World<D>& world);

// Renumbers clumps in the order of their first member, so that after grains are
// renumbered in cell order, clumps are too and the member loops read them nearly in order.
template <int D>
void sort_clumps_by_members(World<D>& world);

// Places every member at its clump's position and orientation and gives it the clump's
// rigid velocity (v + omega x r). Used after adding clumps and after integration.
template <int D>
double place_members(World<D>& world);

}  // namespace geodem
