// The time step: the one place that says what happens, in which order.
#pragma once

#include "world/world.hpp"

namespace geodem {

// Advances the world by one time step (see step.cpp for the pipeline).
template <int D>
void step(World<D>& world);

// Sets world.dt from the critical time step when it is automatic.
template <int D>
void update_timestep(World<D>& world);

// Throws InstabilityError naming the first grain with a non-finite state, one that moves
// more than half its radius per step (runaway), or one wholly behind a plane wall (escaped);
// the step runs it every 1000 steps.
template <int D>
void check_finite(const World<D>& world);

}  // namespace geodem
