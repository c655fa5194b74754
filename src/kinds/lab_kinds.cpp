// The lab kinds: kind = "triaxial" and its element tests ("isotropic", "oedometer",
// "simple_shear", "cyclic_triaxial", "direct_shear"; docs/element_tests.md), "pullout",
// "interface_shear" (docs/lab_tests.md).
#include <algorithm>
#include <cstdio>

#include "io/memory_budget.hpp"
#include "io/toml_reader.hpp"
#include "kinds/scenario_kind.hpp"
#include "lab/interface_shear_settings.hpp"
#include "lab/pullout_settings.hpp"
#include "lab/run_interface_shear.hpp"
#include "lab/run_pullout.hpp"
#include "lab/run_triaxial.hpp"
#include "lab/triaxial_settings.hpp"
#include "study/run_studies.hpp"
#include "study/study_comm.hpp"

namespace geodem {

namespace {

bool single_run(const toml::table&) {
  return false;
}

std::string check_triaxial(const toml::table& root, const std::string& file, int, bool) {
  const auto t = read_triaxial(root, file);
  check_memory(file, source_line(root, "sample.count"), "sample.count", t.dimension,
               static_cast<double>(t.count) * members_per_grain(t.grains, t.dimension));
  return "kind = \"" + std::string(lab_kind_name(t.kind)) + "\", dimension " +
         std::to_string(t.dimension);
}

KindRun run_triaxial_kind(const LoadedScenario& l, const std::string& file, const RunOptions& opt,
                          bool overwrite) {
  const TriaxialSettings t = read_triaxial(l.root, file);
  claim_output(opt, overwrite);
  // (the plots of a decomposed run are rank 0's: the others write no history)
  PlotProcess plots =
      t.plots && opt.primary ? PlotProcess::start(opt.out_dir, opt.quiet) : PlotProcess{};
  run_triaxial(t, opt);
  plots.finish();
  return {};
}

// A pull-out over seeds or grain sizes runs its runs as a study does.
bool pullout_series(const toml::table& root) {
  return root["seeds"].value_or(1LL) > 1 || root.contains("refinement");
}

std::string check_pullout(const toml::table& root, const std::string& file, int threads, bool) {
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

KindRun run_pullout_kind(const LoadedScenario& l, const std::string& file, const RunOptions& opt,
                         bool overwrite) {
  const PulloutSettings p = read_pullout(l.root, file);
  char line[256] = "";
  if (p.seeds > 1 || !p.radius_factors.empty()) {
    claim_output(opt, overwrite);  // a resumed series keeps its finished runs
    PlotProcess plots =
        p.plots && comm::rank() == 0 ? PlotProcess::start(opt.out_dir, opt.quiet) : PlotProcess{};
    const auto summary = run_pullout_series(l.root, p, opt);
    if (comm::rank() != 0) return {};
    plots.finish();
    const auto& t = summary["results"]["T_max"];
    if (t.is_object())
      std::snprintf(line, sizeof line, "T_max %.4g N/m (mean of %d seeds, cv %.2g)",
                    t["mean"].get<double>(), p.seeds, t["cv"].get<double>());
    return {summary["results"]["failed_runs"].empty() ? 0 : 1, line};
  }
  claim_output(opt, overwrite);
  // (the plots of a decomposed run are rank 0's: the others write no history)
  PlotProcess plots =
      p.plots && opt.primary ? PlotProcess::start(opt.out_dir, opt.quiet) : PlotProcess{};
  const auto summary = run_pullout(p, opt);
  plots.finish();
  if (!opt.primary) return {};
  const auto& r = summary["results"];
  std::snprintf(line, sizeof line,
                "T_max %.4g N/m, mechanism %s (design: slippage %.4g N/m, soil mass %.4g N/m)",
                r["T_max"].get<double>(), r["mechanism"].get<std::string>().c_str(),
                r["T_analytic_slip"].get<double>(), r["T_analytic_soil"].get<double>());
  return {0, line};
}

std::string check_interface_shear(const toml::table& root, const std::string& file, int, bool) {
  const auto p = read_interface_shear(root, file);
  const double area = p.box_length * (p.box_height + (p.base == "soil" ? p.lower_height : 0.0));
  check_memory(file, source_line(root, "soil.radius"), "soil.radius", 2, discs_in(area, p.radius));
  return "kind = \"interface_shear\", " + std::to_string(p.normal_stress.size()) +
         " normal stresses";
}

KindRun run_interface_shear_kind(const LoadedScenario& l, const std::string& file,
                                 const RunOptions& opt, bool overwrite) {
  const InterfaceShearSettings p = read_interface_shear(l.root, file);
  claim_output(opt, overwrite);
  // (the plots of a decomposed run are rank 0's: the others write no history)
  PlotProcess plots =
      p.plots && opt.primary ? PlotProcess::start(opt.out_dir, opt.quiet) : PlotProcess{};
  const auto summary = run_interface_shear(p, opt);
  plots.finish();
  if (!opt.primary) return {};
  char line[256];
  std::snprintf(line, sizeof line, "interface friction %.4g deg (peak), %.4g deg (residual)",
                summary["results"]["interface_friction_peak_deg"].get<double>(),
                summary["results"]["interface_friction_residual_deg"].get<double>());
  return {0, line};
}

// The triaxial kind and its element tests spread one run over the ranks of mpirun
// (docs/parallel.md), in a box of walls or a periodic cell.
ScenarioKind spread_lab_kind(const char* name, const char* (*reads_as)(const toml::table&)) {
  ScenarioKind k{name, reads_as, true, single_run, check_triaxial, run_triaxial_kind};
  k.decomposes = true;
  return k;
}

}  // namespace

ScenarioKind triaxial_kind() {
  return spread_lab_kind("triaxial", nullptr);
}
// The element tests read their [material] as the triaxial kind does.
const char* as_triaxial(const toml::table&) {
  return "triaxial";
}
ScenarioKind isotropic_kind() {
  return spread_lab_kind("isotropic", as_triaxial);
}
ScenarioKind oedometer_kind() {
  return spread_lab_kind("oedometer", as_triaxial);
}
ScenarioKind simple_shear_kind() {
  return spread_lab_kind("simple_shear", as_triaxial);
}
ScenarioKind direct_shear_kind() {
  return spread_lab_kind("direct_shear", as_triaxial);
}
ScenarioKind cyclic_triaxial_kind() {
  return spread_lab_kind("cyclic_triaxial", as_triaxial);
}
// A single pull-out spreads over the ranks of mpirun; one over seeds or grain sizes shares its
// runs across them.
ScenarioKind pullout_kind() {
  ScenarioKind k{"pullout", nullptr, true, pullout_series, check_pullout, run_pullout_kind};
  k.decomposes = true;
  return k;
}
// The shear box writes no checkpoints: a stopped test is run again. It spreads over the ranks
// of mpirun.
ScenarioKind interface_shear_kind() {
  ScenarioKind k{"interface_shear",       nullptr, false, single_run, check_interface_shear,
                 run_interface_shear_kind};
  k.decomposes = true;
  return k;
}

}  // namespace geodem
