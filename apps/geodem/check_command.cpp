#include "check_command.hpp"

#include <algorithm>
#include <cstdio>

#include "clumps/grain_mix.hpp"
#include "io/memory_budget.hpp"
#include "io/scenario_check.hpp"
#include "io/toml_reader.hpp"
#include "lab/interface_shear_settings.hpp"
#include "lab/pullout_settings.hpp"
#include "lab/triaxial_settings.hpp"
#include "scene/build_scene.hpp"
#include "scene/scene_settings.hpp"
#include "study/study_settings.hpp"

namespace {

using namespace geodem;

// Discs or spheres per grain of a grain specification (its largest clump).
template <int D>
double members(const GrainSpec& spec) {
  std::size_t m = 1;
  for (const auto& k : resolve_kinds<D>(spec))
    if (!k.round) m = std::max(m, k.clump.radius.size());
  return static_cast<double>(m);
}
double members(const GrainSpec& spec, int dimension) {
  return dimension == 2 ? members<2>(spec) : members<3>(spec);
}

// Discs of radius r that a dense deposit puts in an area (porosity about 0.2).
double discs_in(double area, double r) {
  return 0.8 * area / (3.14159265358979 * r * r);
}

// Reads the settings of the scenario's kind as a run would and checks that the run fits
// in memory (`threads`: runs side by side of a study); returns what the check reports of
// a sound scenario. A scene's grains are built (clouds that cannot be placed are errors).
std::string read_settings(const std::string& kind, const toml::table& root, const std::string& file,
                          int threads, bool build) {
  if (kind == "series") {
    const auto s = read_series(root, file);
    const double most = static_cast<double>(*std::max_element(s.counts.begin(), s.counts.end()));
    const int runs = static_cast<int>(s.counts.size()) * s.seeds;
    check_memory(file, source_line(root, "series.counts"), "series.counts", s.study.check.dimension,
                 most * members(s.study.check.grains, s.study.check.dimension),
                 std::min(threads, runs));
    return "kind = \"series\"";
  }
  if (kind == "rate_study") return read_rate_study(root, file), "kind = \"rate_study\"";
  if (kind == "calibrate") {
    if (is_interface_calibration(root))
      return read_interface_calibrate(root, file), "kind = \"calibrate\", interface";
    return read_calibrate(root, file), "kind = \"calibrate\"";
  }
  if (kind == "triaxial") {
    const auto t = read_triaxial(root, file);
    check_memory(file, source_line(root, "sample.count"), "sample.count", t.dimension,
                 static_cast<double>(t.count) * members(t.grains, t.dimension));
    return "kind = \"triaxial\", dimension " + std::to_string(t.dimension);
  }
  if (kind == "pullout") {
    const auto p = read_pullout(root, file);
    double smallest = 1.0;
    for (double f : p.radius_factors) smallest = std::min(smallest, f);
    const double r = p.radius * smallest;
    const double area = p.box_length * (p.foundation + p.anchor.cover + 2.0 * r);
    const int runs = p.seeds * std::max<int>(1, static_cast<int>(p.radius_factors.size()));
    check_memory(file, source_line(root, "soil.radius"), "soil.radius", 2, discs_in(area, r),
                 std::min(threads, runs));
    return "kind = \"pullout\", shape " + p.anchor.shape;
  }
  if (kind == "interface_shear") {
    const auto p = read_interface_shear(root, file);
    const double area = p.box_length * (p.box_height + (p.base == "soil" ? p.lower_height : 0.0));
    check_memory(file, source_line(root, "soil.radius"), "soil.radius", 2,
                 discs_in(area, p.radius));
    return "kind = \"interface_shear\", " + std::to_string(p.normal_stress.size()) +
           " normal stresses";
  }
  const SceneSettings s = read_scene(root, file);
  double grains = static_cast<double>(s.particles.size());
  std::size_t largest = 0;  // the cloud the message names
  for (std::size_t k = 0; k < s.clouds.size(); ++k) {
    grains += static_cast<double>(s.clouds[k].count);
    if (s.clouds[k].count > s.clouds[largest].count) largest = k;
  }
  const std::string key = "clouds." + std::to_string(largest) + ".count";
  check_memory(file, source_line(root, key), key, s.dimension, grains);
  if (build) {
    if (s.dimension == 2) {
      World<2> w;
      build_world(s, w);
    } else {
      World<3> w;
      build_world(s, w);
    }
  }
  return "kind = \"" + kind + "\", dimension " + std::to_string(s.dimension);
}

}  // namespace

int check_scenario(geodem::LoadedScenario& l, const std::string& file, int threads) {
  std::string ok;
  const auto found = geodem::find_scenario_problems(l.root, [&](const toml::table& root) {
    ok = read_settings(l.kind, root, file, threads, true);
  });
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

void check_run_memory(const geodem::LoadedScenario& l, const std::string& file, int threads) {
  read_settings(l.kind, l.root, file, threads, false);
}
