// Settings of a `kind = "pullout"` scenario (docs/lab_tests.md, "Pull-out"): a 2D soil
// box filled by gravity deposition, a geosynthetic sheet anchored in it (run-out, L- or
// V-shaped trench), an optional surcharge, and the pull of the sheet's free end.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/checkpoint.hpp"
#include "io/toml_reader.hpp"
#include "lab/deposit_settings.hpp"

namespace geodem {

struct AnchorGeometry {
  std::string shape = "runout";  // "runout" | "L" | "V"
  double runout_length = 0.6;    // horizontal embedded length from the front wall (m)
  double cover = 0.15;           // soil thickness above the run-out (m)
  double trench_depth = 0.0;     // below the run-out level (L, V)
  double trench_width = 0.0;     // L: width of the trench behind the sheet; V: top width
  double free_length = 0.04;     // sheet outside the box, up to the pulled end
  // Above the run-out level at x = 0: "free" (the cover ends in a free face, as at the
  // crest of a slope) or "wall" (a rigid, smooth front wall, as in a pull-out box).
  std::string front = "wall";
  // Radius of the trench's front edge, round which the sheet turns (L, V; 0: sharp).
  double edge_radius = 0.0;
};

struct PulloutSettings : DepositedSoil, SheetSettings, DepositTime {
  std::string file;
  std::uint64_t seed = 1;
  // Statistics of the structure: seeds seed, seed + 1, ... (runs side by side), and the
  // grain refinement: the whole series again with the grains scaled by each factor
  // (docs/lab_tests.md, "Pull-out over seeds and grain sizes").
  int seeds = 1;
  std::vector<double> radius_factors;  // [refinement] radius_factors; empty: none
  // [box]
  double box_length = 1.2;  // m
  double foundation = 0.2;  // soil thickness below the run-out level (m)
  // [soil] and [sheet]: DepositedSoil, SheetSettings
  // [anchor]
  AnchorGeometry anchor;
  // [surcharge]
  double surcharge = 0.0;  // Pa on the surface
  // [pull]
  double rate = 0.02;  // m/s
  double max_displacement = 0.05;
  double pull_damping = 0.2;
  int history_points = 200;
  std::vector<double> profiles_at;  // displacements at which tension profiles are written
  // [analytic]
  double soil_friction_deg = 35.0;           // macroscopic friction angle of the soil (for K0)
  double soil_cohesion = 0.0;                // macroscopic cohesion of the soil (Pa)
  double earth_pressure_coefficient = -1.0;  // < 0: Jaky K0 = 1 - sin(phi)
  // earth_pressure_coefficient = "measured": the lateral stress the soil holds on the box's
  // smooth back wall when the pull starts, over its vertical stress (docs/anchorage_design.md).
  bool earth_pressure_measured = false;
  // Macroscopic interface friction and adhesion, as an interface shear test measures them
  // (< 0: the sheet's local interface friction; docs/lab_tests.md, "Interface shear").
  double interface_macro_friction_deg = -1.0;
  // The interface friction of the slippage estimate: the macroscopic one when given, else
  // the sheet's local one.
  double macro_interface_deg() const {
    return interface_macro_friction_deg >= 0.0 ? interface_macro_friction_deg
                                               : interface_friction_deg;
  }
  double interface_adhesion = 0.0;
  // [time]: DepositTime
  // [output]
  bool vtk = true, plots = true;
  bool vtk_contacts = false;  // the contact network (force chains) in each VTK frame
  CheckpointSpec checkpoint;  // [checkpoint]
  int columns = 24;           // colour bands across the box
  nlohmann::json resolved;
};

PulloutSettings read_pullout(const toml::table& root, const std::string& file);

}  // namespace geodem
