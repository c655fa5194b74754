// Settings of a `kind = "pullout"` scenario (docs/lab_tests.md, "Pull-out"): a 2D soil
// box filled by gravity deposition, a geosynthetic sheet anchored in it (run-out, L- or
// V-shaped trench), an optional surcharge, and the pull of the sheet's free end.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clumps/grain_mix.hpp"
#include "io/checkpoint.hpp"
#include "io/toml_reader.hpp"
#include "materials/material.hpp"

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
};

struct PulloutSettings {
  std::string file;
  std::uint64_t seed = 1;
  // [box]
  double box_length = 1.2;  // m
  double foundation = 0.2;  // soil thickness below the run-out level (m)
  // [soil]
  Material soil, wall;
  GrainSpec grains;
  double radius = 0.01;  // mean grain scale (m): the radius of round grains
  double radius_fuzz = 0.25;
  double layer_thickness = 0.1;     // deposition layers (m)
  double settle_unbalanced = 0.01;  // a layer is at rest below this unbalanced force
  bool bonds = false;               // cohesive soil: bond the contacts after filling
  double bond_gap_tolerance = 0.0;
  double deposit_damping = 0.4;
  // Contact friction while the soil is deposited (< 0: the soil's own): lower friction
  // packs it denser, as the friction reduction of the triaxial test does.
  double deposit_friction_deg = -1.0;
  // [anchor]
  AnchorGeometry anchor;
  // [sheet]
  double stiffness_J = 1e5;     // N/m
  double element_length = 0.0;  // 0: the mean grain diameter
  double interface_friction_deg = 34.0;
  double mass_per_area = 0.5;  // kg/m^2
  double thickness = 0.002;    // m (contact radius of the elements is half of it)
  double bending = 0.0;        // N m/rad per m width at each node
  bool mass_scaling = true;    // raise node masses so the sheet does not set the time step
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
  double earth_pressure_coefficient = -1.0;  // < 0: Jaky K0 = 1 - sin(phi)
  // [time]
  double dt_safety = 0.8;
  int dt_update_interval = 20;
  std::uint64_t max_settle_steps = 400'000;
  // [output]
  bool vtk = true, plots = true;
  CheckpointSpec checkpoint;  // [checkpoint]
  int columns = 24;           // colour bands across the box
  nlohmann::json resolved;
};

PulloutSettings read_pullout(const toml::table& root, const std::string& file);

}  // namespace geodem
