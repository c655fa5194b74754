#include "io/scenario_file.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "io/material_file.hpp"
#include "io/toml_reader.hpp"
#include "lab/interface_shear_settings.hpp"
#include "lab/pullout_settings.hpp"
#include "lab/triaxial_settings.hpp"
#include "scene/scene_settings.hpp"
#include "study/study_settings.hpp"

namespace geodem {

namespace {

LoadedScenario finish_loading(toml::table root, const std::vector<std::string>& overrides,
                              const std::string& file) {
  LoadedScenario l{std::move(root), ""};
  for (const auto& o : overrides) apply_override(l.root, o, file);
  const toml::node* kind = l.root.get("kind");
  if (!kind) throw InputError(file, 1, "kind", "missing; expected kind = \"scene\"");
  if (!kind->is_string())
    throw InputError(file, static_cast<int>(kind->source().begin.line), "kind",
                     "expected a string");
  l.kind = *kind->value<std::string>();
  const auto& kinds = scenario_kinds();
  if (std::find(kinds.begin(), kinds.end(), l.kind) == kinds.end()) {
    std::string known;
    for (const auto& k : kinds) known += (known.empty() ? "\"" : ", \"") + k + "\"";
    throw InputError(file, static_cast<int>(kind->source().begin.line), "kind",
                     "unknown kind \"" + l.kind + "\"; expected one of " + known);
  }
  // An interface calibration's material sits in [soil], as in the interface shear test.
  const bool soil_study = l.kind == "calibrate" && is_interface_calibration(l.root);
  expand_material_reference(l.root, soil_study ? "interface_shear" : l.kind, file);
  return l;
}

}  // namespace

const std::vector<std::string>& scenario_kinds() {
  static const std::vector<std::string> kinds = {
      "scene", "triaxial", "pullout", "interface_shear", "series", "rate_study", "calibrate"};
  return kinds;
}

LoadedScenario load_scenario(const std::string& file, const std::vector<std::string>& overrides) {
  return finish_loading(parse_toml_file(file), overrides, file);
}

LoadedScenario load_scenario_text(const std::string& text, const std::string& name) {
  return finish_loading(parse_toml_text(text, name), {}, name);
}

void check_scenario_settings(const LoadedScenario& l, const std::string& file) {
  if (l.kind == "scene") {
    (void)read_scene(l.root, file);
  } else if (l.kind == "triaxial") {
    (void)read_triaxial(l.root, file);
  } else if (l.kind == "pullout") {
    (void)read_pullout(l.root, file);
  } else if (l.kind == "interface_shear") {
    (void)read_interface_shear(l.root, file);
  } else if (l.kind == "series") {
    (void)read_series(l.root, file);
  } else if (l.kind == "rate_study") {
    (void)read_rate_study(l.root, file);
  } else if (is_interface_calibration(l.root)) {
    (void)read_interface_calibrate(l.root, file);
  } else {
    (void)read_calibrate(l.root, file);
  }
}

}  // namespace geodem
