// The contact force stage: every listed grain-grain and grain-wall pair.
#pragma once

#include "world/world.hpp"

namespace geodem {

// Sets the grains' forces and torques to those of their contacts and sums wall forces. When
// world.measure_this_step is set, also fills world.stats (stress, force sums).
template <int D>
void compute_contact_forces(World<D>& world);

}  // namespace geodem
