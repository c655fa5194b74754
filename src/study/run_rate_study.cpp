// kind = "rate_study": strain-rate effects (source paper, section 2.5). The same sample
// (same seeds) is sheared at each strain rate with each damping coefficient; the peak
// follows sigma_peak = sigma_peak_QS + k D rate, whose intercept is the quasi-static
// value and whose slope bounds the rate that keeps the rate bias within a tolerance.
#include <chrono>
#include <cmath>

#include "base/text.hpp"
#include "io/output_files.hpp"
#include "study/run_studies.hpp"
#include "study/study_analysis.hpp"
#include "study/study_output.hpp"

namespace geodem {

nlohmann::json run_rate_study(const RateStudySettings& s, const RunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const TriaxialSettings& b = s.study.check;
  std::vector<StudyRun> runs;
  struct Tag {
    double rate, damping;
    std::uint64_t seed;
  };
  std::vector<Tag> tags;
  for (double rate : s.strain_rates)
    for (double damping : s.damping)
      for (int k = 0; k < s.seeds; ++k) {
        const std::uint64_t seed = b.seed + static_cast<std::uint64_t>(k);
        StudyRun r;
        r.id = cat("rate", format_number(rate), "_damping", format_number(damping), "_seed", seed);
        r.scenario = s.study.base;
        set_key(r.scenario, "shear.strain_rate", rate);
        set_key(r.scenario, "shear.damping", damping);
        set_key(r.scenario, "seed", static_cast<std::int64_t>(seed));
        // Preparation plus a compression whose length goes as 1/rate.
        r.cost = 1.0 + b.strain_rate / rate;
        runs.push_back(std::move(r));
        tags.push_back({rate, damping, seed});
      }
  StudyExecutor exec({opt.out_dir, s.study.file, opt.quiet, opt.threads});
  const std::vector<nlohmann::json> summaries = exec.run(runs, "rate study");

  std::vector<RateSample> samples;
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!run_completed(summaries[i])) continue;
    samples.push_back({tags[i].rate, tags[i].damping, run_result(summaries[i], s.quantity)});
    used.push_back(i);
  }
  if (samples.size() < 2)
    throw std::runtime_error(cat("fewer than two runs completed; see ", opt.out_dir, "/runs/*/"));
  const RateAnalysis a = analyse_rates(samples, s.tolerance);

  nlohmann::json results;
  results["quantity"] = s.quantity;
  results["confining_stress"] = b.confining_stresses[0];
  results["quasi_static"] = a.quasi_static;
  results["k"] = a.k;
  results["fit"] = {{"intercept", a.fit.intercept},
                    {"slope", a.fit.slope},
                    {"intercept_error", a.fit.intercept_error},
                    {"slope_error", a.fit.slope_error},
                    {"r2", a.fit.r2},
                    {"points", a.fit.points}};
  results["tolerance"] = s.tolerance;
  nlohmann::json per = nlohmann::json::array();
  for (const auto& d : a.per_damping)
    per.push_back({{"damping", d.damping},
                   {"intercept", d.fit.intercept},
                   {"slope", d.fit.slope},
                   {"r2", d.fit.r2},
                   {"k", d.k},
                   {"max_rate", std::isfinite(d.max_rate) ? nlohmann::json(d.max_rate) : nullptr}});
  results["per_damping"] = per;
  nlohmann::json table = nlohmann::json::array();
  for (std::size_t j = 0; j < used.size(); ++j) {
    const std::size_t i = used[j];
    table.push_back({{"strain_rate", tags[i].rate},
                     {"damping", tags[i].damping},
                     {"seed", tags[i].seed},
                     {"value", samples[j].value},
                     {"bias", a.bias[j]},
                     {"inertial_number", run_result(summaries[i], "inertial_number")}});
  }
  results["runs"] = table;
  results["failed_runs"] = failed_runs(runs, summaries);

  if (study_root()) {
    HistoryCsv csv;
    csv.open(cat(opt.out_dir, "/runs.csv"),
             {"strain_rate", "damping", "seed", "value", "bias", "inertial_number"});
    for (const auto& r : table)
      csv.row({r["strain_rate"].get<double>(), r["damping"].get<double>(), r["seed"].get<double>(),
               r["value"].get<double>(), r["bias"].get<double>(),
               r["inertial_number"].get<double>()});
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const nlohmann::json timing = study_timing(summaries, wall_s, exec);
  if (!study_root()) return {{"results", results}, {"timing", timing}};
  return write_run_summary(opt.out_dir, "rate_study", "completed", s.study.resolved, results,
                           timing);
}

}  // namespace geodem
