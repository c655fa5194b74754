// O(N) neighbour search: a uniform cell grid filled by counting sort, then the
// Verlet list (contacts/neighbour_list.hpp) rebuilt with the old history merged in.
#pragma once

#include "world/world.hpp"

namespace geodem {

// A build's scratch (the old rows' copy, the threads' parts of the rows, the force arrays)
// lighter than this stays mapped between builds (world.keep_build_scratch).
constexpr std::size_t kSmallBuildScratch = std::size_t{8} << 20;

// Rebuilds world.nlist from the current positions; keeps every listed pair's history.
template <int D>
void build_neighbour_list(World<D>& world);

// Skin in metres for the world's grains (skin_factor x mean radius).
template <int D>
double skin_length(const World<D>& world);

}  // namespace geodem
