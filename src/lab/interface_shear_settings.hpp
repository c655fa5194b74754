// Settings of a `kind = "interface_shear"` scenario (docs/lab_tests.md, "Interface
// shear"): a 2D box of soil deposited by gravity on a geosynthetic sheet that lies on a
// rigid base (or on a lower layer of soil), consolidated under a plate at each normal
// stress, then sheared by moving the sheet at a constant rate.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/toml_reader.hpp"
#include "lab/deposit_settings.hpp"

namespace geodem {

struct InterfaceShearSettings : DepositedSoil, SheetSettings, DepositTime {
  std::string file;
  std::uint64_t seed = 1;
  // [box]
  double box_length = 0.3;  // m: the sheared length of the interface
  double box_height = 0.1;  // m: soil above the sheet
  // What the sheet lies on: "rigid" (the floor of the box; the sheet slides under the
  // soil) or "soil" (a lower layer of soil, lower_height thick; the sheet is pulled out
  // between the two layers through the side wall, as in a pull-out box).
  std::string base = "rigid";
  double lower_height = 0.0;
  // [shear]
  std::vector<double> normal_stress = {25e3, 50e3, 100e3};  // Pa, one test each
  double rate = 0.005;                                      // m/s of the sheet under the soil
  double max_displacement = 0.03;                           // m
  double damping = 0.2;                                     // local damping while shearing
  // Constant normal stiffness (Pa/m): the plate's target normal stress grows by this much
  // per metre the plate rises while shearing, as a soil round the interface that resists
  // its dilation (the constant-normal-stiffness test); 0 holds the normal stress constant.
  double normal_stiffness = 0.0;
  double residual_from = 0.8;             // the residual state: displacements past this fraction
  double consolidation_tolerance = 0.01;  // plate stress within this fraction of its target
  int history_points = 200;               // rows of each test in history.csv
  // [time]: DepositTime
  // [output]
  bool vtk = true, plots = true;
  bool vtk_contacts = false;  // the contact network (force chains) in each VTK frame
  nlohmann::json resolved;
};

InterfaceShearSettings read_interface_shear(const toml::table& root, const std::string& file);

}  // namespace geodem
