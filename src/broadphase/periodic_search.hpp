// The neighbour search of a periodic cell (world/periodic_cell.hpp): grains are binned in
// the cell's own (fractional) coordinates, bins at least one search reach wide across each
// pair of faces, and each grain meets the grains of the 3^D bins around its own, across the
// faces to the images beyond. A pair records which image of its partner it is with.
#pragma once

#include "world/world.hpp"

namespace geodem {

// Moves every grain (a clump with its centre) back into the cell by whole edge vectors:
// done at each build, so that between builds the listed images stay valid.
template <int D>
void wrap_into_cell(World<D>& world);

// Fills the grain-grain rows (start, other, image; each row sorted by partner) of a periodic
// cell: the pairs within the sum of their radii plus the skin. Throws InputError when the
// cell is less than three reaches (largest diameter plus skin) across: a pair could then be
// within reach through two images.
template <int D>
void list_periodic_pairs(World<D>& world);

// The grains in the order of their bins, for renumbering them in spatial order (the walls'
// grid search does the same with its grid cells): grains near each other in the cell, also
// across the faces' bins, then lie near each other in memory.
template <int D>
std::vector<std::uint32_t> periodic_spatial_order(World<D>& world);

}  // namespace geodem
