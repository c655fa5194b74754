// Settings of the three study kinds (docs/studies.md). A study file is a triaxial
// scenario (dimension, seed, [sample], [material], [compaction], [shear], ...) plus the
// study's own table: [series], [rate_study], or [targets] and [calibrate]. Every run of
// the study is that triaxial scenario with a few keys changed.
#pragma once

#include <toml++/toml.h>

#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lab/interface_shear_settings.hpp"
#include "lab/triaxial_settings.hpp"

namespace geodem {

struct StudyBase {
  std::string file;
  toml::table base;         // the file without its study tables, kind = "triaxial"
  TriaxialSettings check;   // the base read once: early errors and derived values
  nlohmann::json resolved;  // base and study tables, for summary.json
  bool plots = true;        // the study's figures (output.plots)
};

// The result of each run that a series or rate study analyses.
inline const std::vector<std::string>& study_quantities() {
  static const std::vector<std::string> q = {
      "peak_q",        "sigma1_peak",   "phi_peak_deg",  "phi_residual_deg",
      "young_modulus", "poisson_ratio", "dilatancy_deg", "axial_strain_at_peak"};
  return q;
}

struct SeriesSettings {
  StudyBase study;
  std::vector<std::size_t> counts;
  int seeds = 5;
  double tolerance = 0.05;
  bool with_scatter = false;  // criterion = "bias_and_scatter"
  std::string quantity = "peak_q";
};

struct RateStudySettings {
  StudyBase study;
  std::vector<double> strain_rates, damping;
  int seeds = 1;
  double tolerance = 0.02;
  std::string quantity = "peak_q";
};

struct CalibrationTargets {
  double phi_peak_deg = 0.0;
  double cohesion = 0.0;  // Pa
  // Optional targets: NaN when not given.
  double young_modulus = std::numeric_limits<double>::quiet_NaN();
  double poisson_ratio = std::numeric_limits<double>::quiet_NaN();
  double phi_residual_deg = std::numeric_limits<double>::quiet_NaN();
  double unit_weight = std::numeric_limits<double>::quiet_NaN();  // N/m3
};

struct CalibrateSettings {
  StudyBase study;
  CalibrationTargets targets;
  std::string name = "calibrated";  // of the material file
  int seeds = 2, verify_seeds = 3, max_iterations = 8;
  // Search tolerances (mean over the search seeds) and verification tolerances
  // (fresh seeds): friction in degrees, cohesion in Pa, modulus relative.
  double tol_phi_deg = 0.5, tol_cohesion = 500.0, tol_young = 0.05, tol_poisson = 0.02;
  double verify_phi_deg = 1.5, verify_cohesion = 2000.0, verify_young = 0.15, verify_poisson = 0.05;
  double upscale = 2.0;  // grain size factor of the upscaling check (1: none)
  double gravity = 9.81;
};

// kind = "calibrate" over interface shear tests (docs/studies.md, "Interface
// calibration"): the study file is an interface_shear scenario with [targets]
// interface_friction_deg (and optionally interface_adhesion) and [calibrate].
struct InterfaceCalibrateSettings {
  std::string file;
  toml::table base;  // the file without its study tables, kind = "interface_shear"
  InterfaceShearSettings check;
  nlohmann::json resolved;
  bool plots = true;
  double target_friction_deg = 34.0;
  double target_adhesion = std::numeric_limits<double>::quiet_NaN();  // checked, not searched
  std::string name = "calibrated";
  int seeds = 2, verify_seeds = 3, max_iterations = 8;
  double tol_deg = 0.5, verify_deg = 1.5, verify_adhesion = 2000.0;
};

// True when a calibrate file targets an interface ([targets] interface_friction_deg).
bool is_interface_calibration(const toml::table& root);
InterfaceCalibrateSettings read_interface_calibrate(const toml::table& root,
                                                    const std::string& file);

SeriesSettings read_series(const toml::table& root, const std::string& file);
RateStudySettings read_rate_study(const toml::table& root, const std::string& file);
CalibrateSettings read_calibrate(const toml::table& root, const std::string& file);

// Sets a dotted key ("sample.count", "seed") of a run's scenario, making tables on the way.
template <typename T>
void set_key(toml::table& t, const std::string& dotted, T&& value) {
  toml::table* at = &t;
  std::size_t start = 0;
  for (std::size_t dot; (dot = dotted.find('.', start)) != std::string::npos; start = dot + 1) {
    const std::string part = dotted.substr(start, dot - start);
    if (!at->contains(part) || !(*at)[part].is_table()) at->insert_or_assign(part, toml::table{});
    at = (*at)[part].as_table();
  }
  at->insert_or_assign(dotted.substr(start), std::forward<T>(value));
}

}  // namespace geodem
