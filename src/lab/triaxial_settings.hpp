// Settings of a `kind = "triaxial"` scenario (docs/lab_tests.md): the sample, its
// preparation (radius growth to an isotropic stress, then friction reduction to a
// target porosity) and one compression test per confining stress. The element tests
// (isotropic, oedometer, simple shear, cyclic triaxial) share the sample and its
// preparation and replace the compression by their own loading program.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clumps/grain_mix.hpp"
#include "io/checkpoint.hpp"
#include "io/toml_reader.hpp"
#include "lab/element_test_settings.hpp"
#include "materials/material.hpp"

namespace geodem {

struct TriaxialSettings {
  std::string file;
  LabKind kind = LabKind::kTriaxial;
  int dimension = 3;
  std::uint64_t seed = 1;
  // [sample]
  std::vector<double> box;  // m
  bool periodic = false;    // boundary = "periodic": a periodic cell instead of walls
  std::size_t count = 1000;
  double radius_fuzz = 0.3333;
  double initial_porosity = 0.95;
  GrainSpec grains;  // grain = "..." or [[sample.grains]]; [[templates]]
  // [material], [walls]
  Material grain, wall;
  // [bonds]: when cohesive bonds are made ("none", "after_compaction", "before_shear")
  std::string bonds_create = "none";
  double bond_gap_tolerance = 0.0;
  // [time]
  double dt_safety = 0.8;
  int dt_update_interval = 10;
  // [compaction]
  double compaction_stress = 1e4;
  double target_porosity = -1.0;  // < 0: no friction reduction
  double compaction_damping = 0.2;
  double max_multiplier = 0.0;  // 0: 1 + 2e4/young (yade's tutorial)
  double final_max_multiplier = 0.0;
  double stress_tolerance = 0.005;
  double unbalanced_tolerance = 1e-3;
  double friction_factor = 0.95;
  int friction_interval = 500;
  std::uint64_t max_compaction_steps = 2'000'000;
  // [shear]
  double strain_rate = 0.02;
  double max_axial_strain = 0.15;
  std::vector<double> confining_stresses;
  double shear_damping = 0.1;
  double servo_gain = 0.5;
  // drainage = "undrained": compression at constant volume (the lateral axes extend at half
  // (3D) or all (2D) of the axial rate); the excess pore pressure is recorded.
  bool undrained = false;
  std::uint64_t consolidation_max_steps = 100'000;
  std::uint64_t stage_max_steps = 200'000;  // per stress step of an isotropic or oedometer test
  int history_points = 300;
  std::vector<double> vtk_at_strains;
  ElementTestSettings element;  // [loading] of the element tests
  // [output]
  bool vtk = true, plots = true;
  bool vtk_contacts = false;  // the contact network (force chains) in each VTK frame
  CheckpointSpec checkpoint;  // [checkpoint]
  nlohmann::json resolved;
};

TriaxialSettings read_triaxial(const toml::table& root, const std::string& file);

}  // namespace geodem
