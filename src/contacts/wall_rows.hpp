// Grain-wall contacts of one slab's grains, a part of the contact stage
// (contacts/contact_forces.cpp): each listed grain-wall pair's force and torque go to the grain,
// and the wall's force, stiffness and dashpot (and, on measured steps, the contact statistics)
// to the slab's tally.
#pragma once

#include <cstddef>

#include "contacts/slab_tally.hpp"
#include "world/world.hpp"

namespace geodem {

// Whether the walls run in the two passes of contacts/plane_walls.cpp (a lab box's plane walls,
// on the vector paths): not on measured steps nor for contacts with extras, which keep the
// general loop.
template <int D>
bool walls_by_plane_passes(const World<D>& world, bool measure, bool extras);

// The wall contacts of grains [first, last), in grain order; `planes` from
// walls_by_plane_passes.
template <int D, bool Measure, bool Extras>
void wall_rows(World<D>& world, std::size_t first, std::size_t last, SlabTally<D>& tally,
               bool planes);

}  // namespace geodem
