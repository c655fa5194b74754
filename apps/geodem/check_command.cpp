#include "check_command.hpp"

#include <cstdio>

#include "io/scenario_check.hpp"
#include "lab/interface_shear_settings.hpp"
#include "lab/pullout_settings.hpp"
#include "lab/triaxial_settings.hpp"
#include "scene/build_scene.hpp"
#include "scene/scene_settings.hpp"
#include "study/study_settings.hpp"

namespace {

// Reads the settings of the scenario's kind as a run would; returns what the check
// reports of a sound scenario.
std::string read_settings(const std::string& kind, const toml::table& root,
                          const std::string& file) {
  using namespace geodem;
  if (kind == "series") return read_series(root, file), "kind = \"series\"";
  if (kind == "rate_study") return read_rate_study(root, file), "kind = \"rate_study\"";
  if (kind == "calibrate") {
    if (is_interface_calibration(root))
      return read_interface_calibrate(root, file), "kind = \"calibrate\", interface";
    return read_calibrate(root, file), "kind = \"calibrate\"";
  }
  if (kind == "triaxial") {
    const auto t = read_triaxial(root, file);
    return "kind = \"triaxial\", dimension " + std::to_string(t.dimension);
  }
  if (kind == "pullout") {
    const auto p = read_pullout(root, file);
    return "kind = \"pullout\", shape " + p.anchor.shape;
  }
  if (kind == "interface_shear") {
    const auto p = read_interface_shear(root, file);
    return "kind = \"interface_shear\", " + std::to_string(p.normal_stress.size()) +
           " normal stresses";
  }
  const SceneSettings s = read_scene(root, file);
  if (s.dimension == 2) {
    World<2> w;
    build_world(s, w);
  } else {
    World<3> w;
    build_world(s, w);
  }
  return "kind = \"" + kind + "\", dimension " + std::to_string(s.dimension);
}

}  // namespace

int check_scenario(geodem::LoadedScenario& l, const std::string& file) {
  std::string ok;
  const auto found = geodem::find_scenario_problems(
      l.root, [&](const toml::table& root) { ok = read_settings(l.kind, root, file); });
  if (found.errors.empty()) {
    std::printf("%s: ok (%s)\n", file.c_str(), ok.c_str());
    return 0;
  }
  for (const auto& e : found.errors) std::fprintf(stderr, "error: %s\n", e.what());
  const std::size_t n = found.errors.size();
  std::fprintf(stderr, "%s: %zu problem%s%s\n", file.c_str(), n, n == 1 ? "" : "s",
               found.complete ? ""
                              : " (the check stopped at one it cannot read past: fix it and "
                                "check again for those after it)");
  return 2;
}
