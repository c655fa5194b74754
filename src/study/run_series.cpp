// kind = "series": the representativeness of a sample size (source paper, section 2.4).
// The same test is run for each grain count with several seeds; the grain size stays
// that of the base sample (the box grows with the count), so d0/L falls as count^(-1/D).
#include <chrono>
#include <cmath>

#include "base/error.hpp"
#include "base/text.hpp"
#include "io/output_files.hpp"
#include "study/run_studies.hpp"
#include "study/study_analysis.hpp"
#include "study/study_output.hpp"

namespace geodem {

nlohmann::json run_series(const SeriesSettings& s, const RunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const TriaxialSettings& b = s.study.check;
  std::vector<StudyRun> runs;
  struct Tag {
    std::size_t count;
    std::uint64_t seed;
  };
  std::vector<Tag> tags;
  for (std::size_t count : s.counts) {
    const double scale =
        std::pow(static_cast<double>(count) / static_cast<double>(b.count), 1.0 / b.dimension);
    toml::array box;
    for (double l : b.box) box.push_back(l * scale);
    for (int k = 0; k < s.seeds; ++k) {
      const std::uint64_t seed = b.seed + static_cast<std::uint64_t>(k);
      StudyRun r;
      r.id = cat("n", count, "_seed", seed);
      r.scenario = s.study.base;
      set_key(r.scenario, "sample.count", static_cast<std::int64_t>(count));
      set_key(r.scenario, "sample.box", box);
      set_key(r.scenario, "seed", static_cast<std::int64_t>(seed));
      r.cost = static_cast<double>(count);
      runs.push_back(std::move(r));
      tags.push_back({count, seed});
    }
  }
  StudyExecutor exec({opt.out_dir, s.study.file, opt.quiet, opt.threads});
  const std::vector<nlohmann::json> summaries = exec.run(runs, "series");

  std::vector<SizeSample> samples;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!run_completed(summaries[i])) continue;
    samples.push_back({tags[i].count, run_result(summaries[i], "d0_over_L"),
                       run_result(summaries[i], s.quantity)});
  }
  std::size_t counts_left = 0;
  for (std::size_t c : s.counts) {
    for (const auto& x : samples)
      if (x.count == c) {
        ++counts_left;
        break;
      }
  }
  if (counts_left < 2)
    throw std::runtime_error(
        cat("fewer than two grain counts have a completed run; see ", opt.out_dir, "/runs/*/"));
  const SeriesAnalysis a = analyse_series(samples, b.dimension, s.tolerance, s.with_scatter);

  nlohmann::json results;
  results["quantity"] = s.quantity;
  results["confining_stress"] = b.confining_stresses[0];
  results["extrapolated"] = a.extrapolated;
  auto fit_json = [](const LinearFit& f) {
    return nlohmann::json{
        {"intercept", f.intercept},     {"slope", f.slope}, {"intercept_error", f.intercept_error},
        {"slope_error", f.slope_error}, {"r2", f.r2},       {"points", f.points}};
  };
  results["mean_fit"] = fit_json(a.mean_fit);
  results["std_fit"] = fit_json(a.std_fit);
  results["size_constant"] = a.size_constant;
  results["tolerance"] = s.tolerance;
  results["criterion"] = s.with_scatter ? "bias_and_scatter" : "bias";
  results["d0_over_L_for_tolerance"] = a.d0_over_L_for_tolerance;
  results["count_for_tolerance"] =
      std::isfinite(a.count_for_tolerance) ? nlohmann::json(a.count_for_tolerance) : nullptr;
  results["smallest_tested_count"] = a.smallest_tested_count;
  nlohmann::json groups = nlohmann::json::array();
  for (const auto& g : a.groups)
    groups.push_back({{"count", g.count},
                      {"runs", g.runs},
                      {"d0_over_L", g.d0_over_L},
                      {"mean", g.mean},
                      {"std", g.std},
                      {"bias", g.bias},
                      {"bias_fit", g.bias_fit},
                      {"scatter", g.scatter},
                      {"scatter_fit", g.scatter_fit}});
  results["groups"] = groups;
  results["failed_runs"] = failed_runs(runs, summaries);

  if (study_root()) {
    HistoryCsv table;
    table.open(cat(opt.out_dir, "/runs.csv"),
               {"count", "seed", "d0_over_L", "value", "porosity_initial", "peak_q", "phi_peak_deg",
                "young_modulus", "inertial_number"});
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (!run_completed(summaries[i])) continue;
      const auto& r = summaries[i];
      table.row({static_cast<double>(tags[i].count), static_cast<double>(tags[i].seed),
                 run_result(r, "d0_over_L"), run_result(r, s.quantity),
                 run_result(r, "porosity_initial"), run_result(r, "peak_q"),
                 run_result(r, "phi_peak_deg"), run_result(r, "young_modulus"),
                 run_result(r, "inertial_number")});
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const nlohmann::json timing = study_timing(summaries, wall_s, exec);
  if (!study_root()) return {{"results", results}, {"timing", timing}};
  return write_run_summary(opt.out_dir, "series", "completed", s.study.resolved, results, timing);
}

}  // namespace geodem
