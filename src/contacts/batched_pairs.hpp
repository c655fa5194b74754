// The grain-grain pair loop of one slab in batches (contacts/contact_batch.hpp): for contacts
// without extras (bonds, rolling springs), in a box or a periodic cell.
#pragma once

#include <cstddef>
#include <vector>

#include "base/parallel.hpp"
#include "contacts/slab_tally.hpp"
#include "world/world.hpp"

namespace geodem {

// Whether the batch kernel has the formulas of every one of these laws (else the scalar loop
// runs).
bool batch_kernel_has(const std::vector<PairLaw>& laws);

// Whether every grain is of one material, so that one pair law holds for every grain pair (the
// gather pass then runs in vector lanes: contacts/pair_gather.hpp).
template <int D>
bool grains_of_one_material(const World<D>& world);

// Forces of the grain-grain contacts listed in the rows [first, last), added to the grains in
// the order of the scalar loop (contacts/contact_forces.cpp), with the same bits. `one_law`:
// grains_of_one_material holds.
template <int D, bool Measure, bool Periodic>
void batched_pair_rows(World<D>& world, std::size_t first, std::size_t last, SlabTally<D>& t,
                       typename SlabCrossings<SlabCrossing<D>>::Writer crossing, bool one_law);

}  // namespace geodem
