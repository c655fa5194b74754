// The study kinds: kind = "series", "rate_study", "calibrate" (docs/studies.md). Their runs
// go to `--threads` workers on each MPI rank; rank 0 reports.
#include <algorithm>
#include <cstdio>
#include <utility>

#include "io/memory_budget.hpp"
#include "io/toml_reader.hpp"
#include "kinds/scenario_kind.hpp"
#include "study/run_studies.hpp"
#include "study/study_comm.hpp"
#include "study/study_settings.hpp"

namespace geodem {

namespace {

bool shared(const toml::table&) {
  return true;
}

// A study's plotting child (rank 0 only), started while the study runs.
PlotProcess plots_for(const RunOptions& opt, bool plots) {
  return plots && comm::rank() == 0 ? PlotProcess::start(opt.out_dir, opt.quiet) : PlotProcess{};
}

// After a study: its plots, and the runs that did not complete (exit 3 when one was unstable,
// else 1).
KindRun finish(const nlohmann::json& summary, PlotProcess plots) {
  if (comm::rank() != 0) return {};
  plots.finish();
  const auto& failed = summary["results"]["failed_runs"];
  if (failed.empty()) return {};
  std::fprintf(stderr, "warning: %zu run(s) did not complete (results.failed_runs):\n",
               failed.size());
  bool unstable = false;
  for (const auto& f : failed) {
    std::fprintf(stderr, "  %s: %s\n", f["id"].get<std::string>().c_str(),
                 f["error"].get<std::string>().c_str());
    unstable = unstable || f["status"] == "unstable";
  }
  return {unstable ? 3 : 1, ""};
}

std::string check_series(const toml::table& root, const std::string& file, int threads, bool) {
  const auto s = read_series(root, file);
  const double most = static_cast<double>(*std::max_element(s.counts.begin(), s.counts.end()));
  const int runs = static_cast<int>(s.counts.size()) * s.seeds;
  check_memory(file, source_line(root, "series.counts"), "series.counts", s.study.check.dimension,
               most * members_per_grain(s.study.check.grains, s.study.check.dimension),
               std::min(threads, runs));
  return "kind = \"series\"";
}

KindRun run_series_kind(const LoadedScenario& l, const std::string& file, const RunOptions& opt,
                        bool overwrite) {
  const auto s = read_series(l.root, file);
  claim_output(opt, overwrite);
  auto plots = plots_for(opt, s.study.plots);
  return finish(run_series(s, opt), std::move(plots));
}

std::string check_rate_study(const toml::table& root, const std::string& file, int, bool) {
  (void)read_rate_study(root, file);
  return "kind = \"rate_study\"";
}

KindRun run_rate_study_kind(const LoadedScenario& l, const std::string& file, const RunOptions& opt,
                            bool overwrite) {
  const auto s = read_rate_study(l.root, file);
  claim_output(opt, overwrite);
  auto plots = plots_for(opt, s.study.plots);
  return finish(run_rate_study(s, opt), std::move(plots));
}

// A calibration of the soil-sheet interface reads its material from [soil], as the interface
// shear test does; one of the soil from [material], as the triaxial test does.
const char* calibrate_materials(const toml::table& root) {
  return is_interface_calibration(root) ? "interface_shear" : "calibrate";
}

std::string check_calibrate(const toml::table& root, const std::string& file, int, bool) {
  if (is_interface_calibration(root))
    return read_interface_calibrate(root, file), "kind = \"calibrate\", interface";
  return read_calibrate(root, file), "kind = \"calibrate\"";
}

KindRun run_calibrate_kind(const LoadedScenario& l, const std::string& file, const RunOptions& opt,
                           bool overwrite) {
  if (is_interface_calibration(l.root)) {
    const auto s = read_interface_calibrate(l.root, file);
    claim_output(opt, overwrite);
    auto plots = plots_for(opt, s.plots);
    return finish(run_interface_calibrate(s, opt), std::move(plots));
  }
  const auto s = read_calibrate(l.root, file);
  claim_output(opt, overwrite);
  auto plots = plots_for(opt, s.study.plots);
  return finish(run_calibrate(s, opt), std::move(plots));
}

}  // namespace

ScenarioKind series_kind() {
  return {"series", nullptr, true, shared, check_series, run_series_kind};
}
ScenarioKind rate_study_kind() {
  return {"rate_study", nullptr, true, shared, check_rate_study, run_rate_study_kind};
}
ScenarioKind calibrate_kind() {
  return {"calibrate", calibrate_materials, true, shared, check_calibrate, run_calibrate_kind};
}

}  // namespace geodem
