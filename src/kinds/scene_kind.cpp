// kind = "scene" (docs/scenarios.md).
#include <cstdio>

#include "io/memory_budget.hpp"
#include "io/toml_reader.hpp"
#include "kinds/scenario_kind.hpp"
#include "scene/build_scene.hpp"
#include "scene/run_scene.hpp"
#include "scene/scene_settings.hpp"
#include "study/study_comm.hpp"

namespace geodem {

namespace {

std::string check(const toml::table& root, const std::string& file, int, bool build) {
  const SceneSettings s = read_scene(root, file);
  double grains = static_cast<double>(s.particles.size());
  std::size_t largest = 0;  // the cloud the message names
  for (std::size_t k = 0; k < s.clouds.size(); ++k) {
    grains += static_cast<double>(s.clouds[k].count);
    if (s.clouds[k].count > s.clouds[largest].count) largest = k;
  }
  const std::string key = "clouds." + std::to_string(largest) + ".count";
  check_memory(file, source_line(root, key), key, s.dimension, grains);
  if (build) {  // clouds that cannot be placed are input errors
    if (s.dimension == 2) {
      World<2> w;
      build_world(s, w);
    } else {
      World<3> w;
      build_world(s, w);
    }
  }
  return "kind = \"scene\", dimension " + std::to_string(s.dimension);
}

KindRun run(const LoadedScenario& l, const std::string& file, const RunOptions& opt,
            bool overwrite) {
  const SceneSettings s = read_scene(l.root, file);
  claim_output(opt, overwrite);
  // (the plots of a decomposed run are rank 0's: the others write no history)
  const bool plot = s.output.plots && (!opt.decompose || comm::rank() == 0);
  PlotProcess plots = plot ? PlotProcess::start(opt.out_dir, opt.quiet) : PlotProcess{};
  const auto summary = run_scene(s, opt);
  plots.finish();
  char line[256];
  std::snprintf(line, sizeof line, "%s steps, %.3g s simulated",
                summary["results"]["steps"].dump().c_str(),
                summary["results"]["time"].get<double>());
  return {0, line};
}

}  // namespace

ScenarioKind scene_kind() {
  ScenarioKind k{"scene", nullptr, true, [](const toml::table&) { return false; }, check, run};
  k.decomposes = true;
  return k;
}

}  // namespace geodem
