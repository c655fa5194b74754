// A pull-out over several seeds and grain sizes (docs/lab_tests.md, "Pull-out over seeds
// and grain sizes"): the scenario's runs with seeds seed, seed + 1, ... and, with
// [refinement], the same again with the grains scaled by each factor (same micro
// parameters, same geometry and sheet, its elements scaled with the grains); the runs go side by
// side (StudyExecutor, as the studies' runs). Reports, for each grain size, the mean, spread and
// range of T_max, of the displacement at T_max and of the soil's displacement, the mechanisms, and
// the capacity against d50 / cover with its extrapolation to fine grains.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "base/text.hpp"
#include "io/output_files.hpp"
#include "study/linear_fit.hpp"
#include "study/run_studies.hpp"
#include "study/study_output.hpp"

namespace geodem {

namespace {

nlohmann::json stats(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  const double m = mean(v), sd = standard_deviation(v);
  return {{"mean", m},
          {"std", sd},
          {"cv", m != 0.0 ? sd / std::abs(m) : 0.0},
          {"min", *std::min_element(v.begin(), v.end())},
          {"max", *std::max_element(v.begin(), v.end())},
          {"count", v.size()}};
}

// A number of a run's summary; NaN when it is null (JSON has no NaN: a NaN result, such
// as an estimate of a failed measurement, is written as null).
double number(const nlohmann::json& j) {
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

nlohmann::json run_pullout_series(const toml::table& root, const PulloutSettings& s,
                                  const RunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<double> factors =
      s.radius_factors.empty() ? std::vector<double>{1.0} : s.radius_factors;
  std::vector<StudyRun> runs;
  for (double f : factors)
    for (int k = 0; k < s.seeds; ++k) {
      StudyRun r;
      const std::uint64_t seed = s.seed + static_cast<std::uint64_t>(k);
      r.id = factors.size() > 1 ? cat("size", format_number(f), "_seed", seed) : cat("seed", seed);
      r.scenario = root;
      r.scenario.erase("seeds");
      r.scenario.erase("refinement");
      set_key(r.scenario, "seed", static_cast<std::int64_t>(seed));
      set_key(r.scenario, "soil.radius", s.radius * f);
      // The same structure at every grain size: the sheet's thickness and flexural rigidity
      // (EI = bending stiffness per node x element length) stay; its elements shorten with
      // the grains, as they are part of the interface's micro model (elements longer than
      // the grains catch on them one after another: docs/anchorage_design.md).
      set_key(r.scenario, "sheet.element_length", s.element_length * f);
      set_key(r.scenario, "sheet.bending_stiffness", s.bending / f);
      set_key(r.scenario, "sheet.thickness", s.thickness);
      set_key(r.scenario, "output.plots", false);
      set_key(r.scenario, "output.vtk", false);
      r.cost = 1.0 / (f * f);  // grains ~ 1 / f^2
      runs.push_back(std::move(r));
    }
  StudyExecutor exec({opt.out_dir, s.file, opt.quiet, opt.threads});
  const std::vector<nlohmann::json> summaries = exec.run(runs, "pull-out runs");

  HistoryCsv csv;
  if (study_root())
    csv.open(cat(opt.out_dir, "/pullout_runs.csv"),
             {"radius_factor", "seed", "grains", "T_max", "displacement_at_T_max",
              "soil_displacement_median", "soil_ratio", "sheet_slip_ratio", "slippage",
              "T_analytic_slip", "T_analytic_soil", "wall_s", "T_residual"});
  nlohmann::json groups = nlohmann::json::array();
  std::vector<double> x_fit, t_fit, r_fit;
  std::size_t i = 0;
  for (double f : factors) {
    std::vector<double> tmax, dmax, soil, grains, slip, soil_est, wall, residual;
    std::map<std::string, int> mechanisms;
    nlohmann::json ids = nlohmann::json::array();
    for (int k = 0; k < s.seeds; ++k, ++i) {
      const nlohmann::json& sm = summaries[i];
      ids.push_back(runs[i].id);
      if (!run_completed(sm)) continue;
      const auto& r = sm["results"];
      tmax.push_back(number(r["T_max"]));
      dmax.push_back(number(r["displacement_at_T_max"]));
      soil.push_back(number(r["soil_displacement_median"]));
      grains.push_back(number(r["grains"]));
      slip.push_back(number(r["T_analytic_slip"]));
      soil_est.push_back(number(r["T_analytic_soil"]));
      wall.push_back(number(sm["timing"]["wall_s"]));
      residual.push_back(number(r["T_residual"]));
      const std::string m = r["mechanism"].get<std::string>();
      ++mechanisms[m];
      const auto& mm = r["mechanism_measures"];
      if (study_root())
        csv.row({f, static_cast<double>(s.seed) + k, grains.back(), tmax.back(), dmax.back(),
                 soil.back(), number(mm["soil_ratio"]), number(mm["sheet_slip_ratio"]),
                 m == "slippage" ? 1.0 : 0.0, slip.back(), soil_est.back(), wall.back(),
                 residual.back()});
    }
    nlohmann::json g;
    g["radius_factor"] = f;
    g["radius"] = s.radius * f;
    g["d50_over_cover"] = 2.0 * s.radius * f / s.anchor.cover;
    g["runs"] = ids;
    g["completed"] = tmax.size();
    g["T_max"] = stats(tmax);
    g["T_residual"] = stats(residual);
    g["displacement_at_T_max"] = stats(dmax);
    g["soil_displacement_median"] = stats(soil);
    g["grains"] = stats(grains);
    g["T_analytic_slip"] = stats(slip);
    g["T_analytic_soil"] = stats(soil_est);
    g["wall_s"] = stats(wall);
    g["mechanisms"] = mechanisms;
    if (!tmax.empty()) {
      const double design = std::min(mean(slip), mean(soil_est));
      g["T_max_over_slip"] = mean(tmax) / mean(slip);
      g["T_max_over_soil"] = mean(tmax) / mean(soil_est);
      g["T_max_over_design"] = mean(tmax) / design;
      x_fit.push_back(g["d50_over_cover"].get<double>());
      t_fit.push_back(mean(tmax));
      r_fit.push_back(mean(residual));
    }
    groups.push_back(std::move(g));
  }
  nlohmann::json results;
  results["seeds"] = s.seeds;
  results["groups"] = groups;
  // The first grain size's statistics, at the top for a plain seed series.
  results["T_max"] = groups[0]["T_max"];
  results["T_residual"] = groups[0]["T_residual"];
  results["mechanisms"] = groups[0]["mechanisms"];
  if (factors.size() > 1 && x_fit.size() >= 2) {
    const LinearFit fit = fit_line(x_fit, t_fit);
    const std::size_t finest = static_cast<std::size_t>(
        std::min_element(factors.begin(), factors.end()) - factors.begin());
    const double t_first = t_fit.front();
    results["refinement"] = {
        {"T_max_fine_limit", fit.intercept},
        {"slope", fit.slope},
        {"r2", fit.r2},
        {"change_finest_vs_first",
         finest < t_fit.size() ? t_fit[finest] / t_first - 1.0 : std::nan("")},
        {"residual_change_finest_vs_first",
         finest < r_fit.size() ? r_fit[finest] / r_fit.front() - 1.0 : std::nan("")}};
  }
  nlohmann::json failed = failed_runs(runs, summaries);
  results["failed_runs"] = failed;
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const nlohmann::json timing = study_timing(summaries, wall_s, exec);
  if (!study_root()) return {{"results", results}, {"timing", timing}};
  return write_run_summary(opt.out_dir, "pullout", failed.empty() ? "completed" : "incomplete",
                           s.resolved, results, timing);
}

}  // namespace geodem
