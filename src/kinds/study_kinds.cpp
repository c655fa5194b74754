// The study kinds: kind = "series", "rate_study", "calibrate" (docs/studies.md). Their runs
// go to `--threads` workers on each MPI rank; rank 0 reports.
#include <algorithm>
#include <cstdio>

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

// After a study: its plots, and the runs that did not complete (exit 3 when one was unstable,
// else 1).
KindRun finish(const nlohmann::json& summary, bool plots, const RunOptions& opt) {
  if (comm::rank() != 0) return {};
  if (plots) make_plots(opt.out_dir, opt.quiet);
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
  return finish(run_series(s, opt), s.study.plots, opt);
}

std::string check_rate_study(const toml::table& root, const std::string& file, int, bool) {
  (void)read_rate_study(root, file);
  return "kind = \"rate_study\"";
}

KindRun run_rate_study_kind(const LoadedScenario& l, const std::string& file, const RunOptions& opt,
                            bool overwrite) {
  const auto s = read_rate_study(l.root, file);
  claim_output(opt, overwrite);
  return finish(run_rate_study(s, opt), s.study.plots, opt);
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
    return finish(run_interface_calibrate(s, opt), s.plots, opt);
  }
  const auto s = read_calibrate(l.root, file);
  claim_output(opt, overwrite);
  return finish(run_calibrate(s, opt), s.study.plots, opt);
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
