// O(N) neighbour search: a uniform cell grid filled by counting sort, then the
// Verlet list (contacts/neighbour_list.hpp) rebuilt with the old history merged in.
#pragma once

#include "world/world.hpp"

namespace geodem {

// Rebuilds world.nlist from the current positions; keeps every listed pair's history.
template <int D>
void build_neighbour_list(World<D>& world);

// Skin in metres for the world's grains (skin_factor x mean radius).
template <int D>
double skin_length(const World<D>& world);

}  // namespace geodem
