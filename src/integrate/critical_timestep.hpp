// Automatic time step, the rule of yade's GlobalStiffnessTimeStepper: each grain's
// stiffness matrix is approximated by its diagonal, summed over its contacts
// (translation along axis a: kt + (kn - kt) n_a^2; rotation about a: kt lever^2
// (1 - n_a^2)); dt = safety x sqrt(2) x min over grains of sqrt(m / max K_t) and
// sqrt(I / max K_r), times sqrt(1 + z^2) - z for contact dashpots of damping ratio up to z.
// A grain without contacts counts as meeting an equal grain (linear law), or 0.2 x the
// Rayleigh wave time bounds it (Hertz law).
#pragma once

#include "world/world.hpp"

namespace geodem {

template <int D>
double critical_timestep(const World<D>& world);

}  // namespace geodem
