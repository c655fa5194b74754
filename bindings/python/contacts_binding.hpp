// The contact network of a scene as numpy arrays (copies): what force chains, fabric tensors
// and coordination statistics are computed from in Python.
#pragma once

#include <pybind11/pybind11.h>

#include "world/world.hpp"

namespace geodem::python {

// The grain-grain contacts touching (or bonded) at the last step: i, j (grain indices),
// normal (K, D) from i to j, overlap (m), normal_force (the law's elastic part: N, N/m in 2D;
// negative for a bond in tension), tangential_force (K, D) on j, bonded.
template <int D>
pybind11::dict contact_arrays(const World<D>& world);

// The grain-wall contacts touching at the last step: grain, wall (indices; the wall's name
// is Scene.walls[wall]), normal (K, D) from the grain to the wall, overlap, normal_force (the
// law's elastic part, on the wall), tangential_force (K, D) on the wall.
template <int D>
pybind11::dict wall_contact_arrays(const World<D>& world);

}  // namespace geodem::python
