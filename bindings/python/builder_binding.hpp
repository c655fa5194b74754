// Building a scene's world from Python: walls, clumps, clouds, chains and bonds added to a
// Scene2D or Scene3D (docs/python.md).
#pragma once

#include <pybind11/pybind11.h>

namespace geodem::python {

// Adds add_walls, add_clumps, add_cloud, add_chain and create_bonds to the scene classes
// (bind_scenes first).
void bind_builders(pybind11::module_& m);

}  // namespace geodem::python
