// Centred finite differences (leapfrog): velocities live at half steps,
// v(t+dt/2) = v(t-dt/2) + a(t) dt, x(t+dt) = x(t) + v(t+dt/2) dt, with Cundall's
// non-viscous local damping on each force and torque component:
// F_k <- F_k - alpha |F_k| sign(v_k), v_k the on-step estimate v(t-dt/2) + a_k dt/2.
#pragma once

#include "world/world.hpp"

namespace geodem {

template <int D>
void integrate(World<D>& world);

// Moves walls with their velocity (after the grains, same step).
template <int D>
void move_walls(World<D>& world);

}  // namespace geodem
