// Material files: the micro parameters of a soil, ready to use in any scenario. The
// calibration writes them; the project ships the calibrated soils of the source paper
// as presets (presets/*.toml). A scenario names one in its material table:
//   [material] preset = "sand_2d"        (triaxial and studies)
//   [soil] file = "my_soil.toml"          (pull-out; a path relative to the scenario)
// and its own keys there override the file's.
#pragma once

#include <toml++/toml.h>

#include <nlohmann/json.hpp>
#include <string>

namespace geodem {

struct MaterialFile {
  std::string name, source;
  int dimension = 2;
  nlohmann::json material;  // numbers: density, young, kt_over_kn, friction_deg, ...
  std::string grain;        // template or round shape ("" for a mix)
  double radius_fuzz = 0.0;
  double porosity = 0.0;  // of the calibrated samples
  nlohmann::json macro;   // measured macro values, for the record
  // The calibrated soil-sheet interface (null when none): local_friction_deg (the
  // sheet's interface_friction_deg), macro_friction_deg and macro_adhesion (what an
  // interface shear test measures with it), and the sheet it was calibrated with.
  nlohmann::json interface;
};

void write_material_file(const std::string& path, const MaterialFile& m);

// Replaces `preset = ...` / `file = ...` in the scenario's material table ([material],
// or [soil] for the pull-out and interface shear kinds) by the file's values, where the
// scenario does not give them: material keys, the grain shape and radius fuzz, (lab
// tests) the porosity as compaction.target_porosity, and a calibrated interface: the
// sheet's local interface friction and, in a pull-out whose sheet takes it, the
// macroscopic interface friction and adhesion of its design estimate.
void expand_material_reference(toml::table& root, const std::string& kind,
                               const std::string& scenario_file);

// Folder of the shipped presets.
std::string preset_dir();

}  // namespace geodem
