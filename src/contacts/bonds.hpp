// Cohesive bonds: created on demand (after compaction, or between touching grains at
// the start) at the grain-grain contacts whose pair law is cohesive; broken by the
// contact force stage when a strength is exceeded (contacts/contact_law.hpp).
#pragma once

#include <cstddef>

#include "world/world.hpp"

namespace geodem {

// Bonds every listed grain pair with a cohesive law whose gap is at most
// `gap_tolerance` x the smaller radius (0: touching or overlapping). Rebuilds the
// neighbour list first if it is stale. Returns the number of bonds created.
template <int D>
std::size_t create_bonds(World<D>& world, double gap_tolerance = 0.0);

}  // namespace geodem
