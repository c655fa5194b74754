// The periodic cell from Python (docs/python.md): set_periodic, the cell's matrix and velocity
// gradient, its average stress, and the cell servo, on the scene classes.
#pragma once

#include <pybind11/pybind11.h>

namespace geodem::python {

// Adds the periodic cell's calls to Scene2D and Scene3D (bind_scenes first).
void bind_cells(pybind11::module_& m);

}  // namespace geodem::python
