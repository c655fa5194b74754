// Automatic time step, after yade's GlobalStiffnessTimeStepper: each grain's
// stiffness is the sum of its contacts' stiffnesses (normal for translation,
// tangential x lever^2 for rotation); dt = safety x min over grains of
// sqrt(m/K_t), sqrt(I/K_r). Without contacts, each grain is taken in contact with
// an equal grain (linear law) or the Rayleigh wave time is used (Hertz law).
#pragma once

#include "core/world.hpp"

namespace geodem {

template <int D>
double critical_timestep(const World<D>& world);

}  // namespace geodem
