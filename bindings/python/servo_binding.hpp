// The engine's plate servo driven from Python: set_servo, remove_servo and wall_stress on
// the scene classes (docs/python.md).
#pragma once

#include <pybind11/pybind11.h>

namespace geodem::python {

// Adds the servo calls to Scene2D and Scene3D (bind_scenes first).
void bind_servos(pybind11::module_& m);

}  // namespace geodem::python
