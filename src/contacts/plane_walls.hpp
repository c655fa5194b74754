// Grain-wall contacts against plane walls in two passes over chunks of listed pairs, for the
// common case of a lab box: every wall a plane, no contact extras, nothing measured this step.
#pragma once

#include <cstddef>

#include "contacts/slab_tally.hpp"
#include "world/world.hpp"

namespace geodem {

// Whether plane_wall_rows applies to this world (every wall a plane).
template <int D>
bool plane_walls_only(const World<D>& world);

// Forces of the grain-wall pairs listed in the rows [first, last), added to the grains, the walls
// and the slab's sums in the order of the scalar loop (contacts/contact_forces.cpp, grain_walls),
// with the same bits.
template <int D>
void plane_wall_rows(World<D>& world, std::size_t first, std::size_t last, SlabTally<D>& t);

}  // namespace geodem
