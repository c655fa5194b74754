// The engine's plate servo driven from Python (docs/python.md): a wall held at a normal
// stress by controllers/plate_servo.hpp, the one the stages of a scene use, stepped inside
// the engine (no Python call per step).
#include "servo_binding.hpp"

#include <algorithm>
#include <memory>

#include "base/error.hpp"
#include "controllers/plate_servo.hpp"
#include "scene_binding.hpp"

namespace geodem::python {

namespace {

// Drops the servo of wall `index`, if any; the world then sums wall dashpots only while a
// servo is left to count them.
template <int D>
void drop_servo(World<D>& w, std::size_t index) {
  std::erase_if(w.controllers, [index](const auto& c) {
    const auto* servo = dynamic_cast<const PlateServo<D>*>(c.get());
    return servo && servo->wall() == index;
  });
  w.tally_wall_dashpots = std::any_of(w.controllers.begin(), w.controllers.end(), [](auto& c) {
    return dynamic_cast<const PlateServo<D>*>(c.get()) != nullptr;
  });
}

template <int D>
void bind_servo(py::module_& m, const char* name) {
  using S = Scene<D>;
  auto cls = py::reinterpret_borrow<py::class_<S>>(m.attr(name));
  cls.def(
         "set_servo",
         [](S& s, const std::string& wall, double stress, double max_speed, double gain,
            double integral_gain) {
           auto& w = s.world();
           const std::size_t i = s.wall_index(wall);
           if (!(w.walls[i].area > 0.0))
             throw InputError("<dict>", 0, "walls." + wall + ".area",
                              "a servo holds a stress: give the wall its area (m^2; m in 2D)");
           if (!(stress > 0.0) || !(max_speed > 0.0) || !(gain > 0.0) || !(integral_gain >= 0.0))
             throw py::value_error(
                 "expected stress > 0, max_speed > 0, gain > 0 and integral_gain >= 0");
           drop_servo(w, i);
           w.walls[i].velocity.setZero();
           w.tally_wall_dashpots = true;  // the servo counts its contacts' dashpots
           w.controllers.push_back(
               std::make_shared<PlateServo<D>>(i, stress, max_speed, gain, integral_gain, true));
         },
         py::arg("wall"), py::arg("stress"), py::arg("max_speed"), py::arg("gain") = 0.5,
         py::arg("integral_gain") = 0.05,
         "Holds the wall at the normal stress `stress` (Pa) from the next step on, moving it "
         "along its normal at most at max_speed (m/s): the plate servo of a scene's stages, "
         "stepped by the engine. Replaces the wall's servo if it had one.")
      .def(
          "remove_servo",
          [](S& s, const std::string& wall) {
            auto& w = s.world();
            const std::size_t i = s.wall_index(wall);
            drop_servo(w, i);
            w.walls[i].velocity.setZero();
          },
          py::arg("wall"), "Stops the wall's servo; the wall stands still.")
      .def(
          "wall_stress",
          [](S& s, const std::string& wall) {
            return s.world().walls[s.wall_index(wall)].normal_stress();
          },
          py::arg("wall"),
          "The normal stress of the grains on the wall at the last step (Pa: its force along "
          "its normal over its area; 0 without an area).");
}

}  // namespace

void bind_servos(py::module_& m) {
  bind_servo<2>(m, "Scene2D");
  bind_servo<3>(m, "Scene3D");
}

}  // namespace geodem::python
