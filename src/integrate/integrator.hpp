// Centred finite differences (leapfrog): velocities live at half steps,
// v(t+dt/2) = v(t-dt/2) + a(t) dt, x(t+dt) = x(t) + v(t+dt/2) dt, with Cundall's
// non-viscous local damping on each force and torque component:
// F_k <- F_k - alpha |F_k| sign(v_k), v_k the on-step estimate v(t-dt/2) + a_k dt/2.
#pragma once

#include "world/world.hpp"

namespace geodem {

template <int D>
void integrate(World<D>& world);

// Moves the grains [first, last) by one step, on the calling thread, as integrate() moves them
// (the same bits on every instruction set); returns their largest speed squared. For the force
// stage, which moves each slab once its forces are complete (world.move_in_force_stage), never
// with tracked orientations (world/step.cpp).
template <int D>
double move_grain_range(World<D>& world, std::size_t first, std::size_t last);

// Moves walls with their velocity (after the grains, same step).
template <int D>
void move_walls(World<D>& world);

}  // namespace geodem
