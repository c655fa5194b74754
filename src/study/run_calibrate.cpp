// kind = "calibrate": micro parameters from macro targets (source paper, section 3.4.1).
// Iterates CalibrationSearch over biaxial/triaxial tests with fixed search seeds (the
// same samples at every iteration, so that the search sees the parameters' effect and
// not the seeds' scatter), then verifies the best parameters with fresh seeds and again
// with grains `upscale` times larger, and writes material.toml.
#include <chrono>
#include <cmath>
#include <set>

#include "base/text.hpp"
#include "io/material_file.hpp"
#include "io/output_files.hpp"
#include "lab/soil_parameters.hpp"
#include "study/calibration_search.hpp"
#include "study/linear_fit.hpp"
#include "study/run_studies.hpp"
#include "study/study_output.hpp"

namespace geodem {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct Evaluation {
  MacroValues macro;  // pooled over all runs
  double porosity = 0.0;
  std::vector<MacroValues> per_seed;
  std::size_t runs = 0;
};

// Macro values of a set of tests: the Mohr-Coulomb fit of all their peaks (or, with one
// confining stress, the mean peak angle and no cohesion), mean modulus, Poisson's ratio
// and residual angle.
MacroValues macro_of(const std::vector<const nlohmann::json*>& tests) {
  std::vector<double> s1, s3, e, nu, res;
  std::set<double> stresses;
  double phi_sum = 0.0;
  for (const auto* t : tests) {
    s1.push_back((*t)["sigma1_peak"].get<double>());
    s3.push_back((*t)["sigma3_peak"].get<double>());
    stresses.insert((*t)["confining_stress"].get<double>());
    e.push_back((*t)["young_modulus"].get<double>());
    nu.push_back((*t)["poisson_ratio"].get<double>());
    res.push_back((*t)["phi_residual_deg"].get<double>());
    phi_sum += (*t)["phi_peak_deg"].get<double>();
  }
  MacroValues m;
  if (stresses.size() >= 2) {
    const MohrCoulomb mc = fit_mohr_coulomb(s1, s3);
    m.phi_peak_deg = mc.phi_deg;
    m.cohesion = mc.cohesion;
  } else {
    m.phi_peak_deg = phi_sum / static_cast<double>(tests.size());
  }
  m.young_modulus = mean(e);
  m.poisson_ratio = mean(nu);
  m.phi_residual_deg = mean(res);
  return m;
}

Evaluation evaluate(const std::vector<nlohmann::json>& summaries) {
  Evaluation ev;
  std::vector<const nlohmann::json*> all;
  std::vector<double> porosity;
  for (const auto& s : summaries) {
    if (!run_completed(s)) continue;
    std::vector<const nlohmann::json*> mine;
    for (const auto& t : s["results"]["tests"]) {
      mine.push_back(&t);
      all.push_back(&t);
      porosity.push_back(t["porosity_initial"].get<double>());
    }
    ev.per_seed.push_back(macro_of(mine));
    ++ev.runs;
  }
  if (all.empty()) throw std::runtime_error("no test of this calibration step completed");
  ev.macro = macro_of(all);
  ev.porosity = mean(porosity);
  return ev;
}

nlohmann::json macro_json(const MacroValues& m) {
  return {{"phi_peak_deg", m.phi_peak_deg},
          {"cohesion", m.cohesion},
          {"young_modulus", m.young_modulus},
          {"poisson_ratio", m.poisson_ratio},
          {"phi_residual_deg", m.phi_residual_deg}};
}

nlohmann::json micro_json(const MicroParameters& p, double shear_ratio, double density) {
  return {{"young", p.young},
          {"kt_over_kn", p.kt_over_kn},
          {"friction_deg", p.friction_deg},
          {"normal_cohesion", p.bond_strength},
          {"shear_cohesion", p.bond_strength * shear_ratio},
          {"rolling_friction", p.rolling_friction},
          {"density", density}};
}

// Standard deviation over seeds of each macro value.
nlohmann::json scatter_json(const std::vector<MacroValues>& v) {
  std::vector<double> phi, c, e, nu, res;
  for (const auto& m : v) {
    phi.push_back(m.phi_peak_deg);
    c.push_back(m.cohesion);
    e.push_back(m.young_modulus);
    nu.push_back(m.poisson_ratio);
    res.push_back(m.phi_residual_deg);
  }
  return {{"phi_peak_deg", standard_deviation(phi)},
          {"cohesion", standard_deviation(c)},
          {"young_modulus", standard_deviation(e)},
          {"poisson_ratio", standard_deviation(nu)},
          {"phi_residual_deg", standard_deviation(res)}};
}

}  // namespace

nlohmann::json run_calibrate(const CalibrateSettings& s, const RunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const TriaxialSettings& b = s.study.check;
  const CalibrationTargets& g = s.targets;
  MicroParameters start;
  start.young = b.grain.young;
  start.kt_over_kn = b.grain.kt_over_kn;
  start.friction_deg = std::atan(b.grain.friction) / kDeg;
  start.bond_strength = b.grain.normal_cohesion;
  start.rolling_friction = b.grain.rolling_friction;
  const double shear_ratio =
      b.grain.normal_cohesion > 0.0 ? b.grain.shear_cohesion / b.grain.normal_cohesion : 1.0;
  double density = b.grain.density;
  SearchTolerances tol{s.tol_phi_deg, s.tol_cohesion, s.tol_young, s.tol_poisson};
  CalibrationSearch search(g, tol, start);

  StudyExecutor exec({opt.out_dir, s.study.file, opt.quiet, opt.threads});
  std::vector<nlohmann::json> all_summaries;
  nlohmann::json failed = nlohmann::json::array();
  auto batch = [&](const std::string& tag, const MicroParameters& p, std::uint64_t first_seed,
                   int seeds, double size_factor) {
    std::vector<StudyRun> runs;
    for (int k = 0; k < seeds; ++k) {
      StudyRun r;
      const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
      r.id = cat(tag, "_seed", seed);
      r.scenario = s.study.base;
      toml::table& mat = *r.scenario["material"].as_table();
      mat.erase("friction");
      const nlohmann::json micro = micro_json(p, shear_ratio, density);
      for (const auto& [key, v] : micro.items()) mat.insert_or_assign(key, v.get<double>());
      if (size_factor != 1.0) {
        toml::array box;
        for (double l : b.box) box.push_back(l * size_factor);
        set_key(r.scenario, "sample.box", box);
      }
      set_key(r.scenario, "seed", static_cast<std::int64_t>(seed));
      runs.push_back(std::move(r));
    }
    auto summaries = exec.run(runs, cat("calibration ", tag));
    for (auto& f : failed_runs(runs, summaries)) failed.push_back(std::move(f));
    all_summaries.insert(all_summaries.end(), summaries.begin(), summaries.end());
    return evaluate(summaries);
  };

  HistoryCsv csv;
  if (study_root())
    csv.open(cat(opt.out_dir, "/calibration.csv"),
             {"iteration", "young", "kt_over_kn", "friction_deg", "normal_cohesion",
              "rolling_friction", "density", "phi_peak_deg", "cohesion", "young_modulus",
              "poisson_ratio", "phi_residual_deg", "porosity", "miss"});
  nlohmann::json iterations = nlohmann::json::array();
  MicroParameters best = start;
  Evaluation best_ev;
  double best_miss = std::numeric_limits<double>::infinity();
  bool converged = false;
  for (int it = 0; it < s.max_iterations && !converged; ++it) {
    const MicroParameters p = search.current();
    const Evaluation ev = batch(cat("iter", it), p, b.seed, s.seeds, 1.0);
    const double miss = search.miss(ev.macro);
    if (study_root())
      csv.row({static_cast<double>(it), p.young, p.kt_over_kn, p.friction_deg, p.bond_strength,
               p.rolling_friction, density, ev.macro.phi_peak_deg, ev.macro.cohesion,
               ev.macro.young_modulus, ev.macro.poisson_ratio, ev.macro.phi_residual_deg,
               ev.porosity, miss});
    iterations.push_back({{"micro", micro_json(p, shear_ratio, density)},
                          {"macro", macro_json(ev.macro)},
                          {"porosity", ev.porosity},
                          {"miss", miss}});
    if (miss < best_miss) best_miss = miss, best = p, best_ev = ev;
    converged = search.record(ev.macro);
    // Grain density for the target unit weight at the porosity the samples reach.
    if (std::isfinite(g.unit_weight)) density = g.unit_weight / (s.gravity * (1.0 - ev.porosity));
  }

  // Verification with fresh seeds, then the same with larger grains.
  const std::uint64_t fresh = b.seed + 1000;
  nlohmann::json results;
  results["converged"] = converged;
  results["iterations"] = iterations;
  results["micro"] = micro_json(best, shear_ratio, density);
  results["search"] = {{"macro", macro_json(best_ev.macro)}, {"miss", best_miss}};
  Evaluation verify = best_ev;
  if (s.verify_seeds > 0) {
    verify = batch("verify", best, fresh, s.verify_seeds, 1.0);
    const MacroValues& m = verify.macro;
    nlohmann::json checks;
    auto check = [&](const char* key, double got, double target, double limit, bool relative) {
      const double err = relative ? got / target - 1.0 : got - target;
      checks[key] = {{"target", target},
                     {"measured", got},
                     {"error", err},
                     {"tolerance", limit},
                     {"met", std::abs(err) <= limit}};
    };
    check("phi_peak_deg", m.phi_peak_deg, g.phi_peak_deg, s.verify_phi_deg, false);
    check("cohesion", m.cohesion, g.cohesion, s.verify_cohesion, false);
    if (std::isfinite(g.young_modulus))
      check("young_modulus", m.young_modulus, g.young_modulus, s.verify_young, true);
    if (std::isfinite(g.poisson_ratio))
      check("poisson_ratio", m.poisson_ratio, g.poisson_ratio, s.verify_poisson, false);
    if (std::isfinite(g.phi_residual_deg))
      check("phi_residual_deg", m.phi_residual_deg, g.phi_residual_deg, s.verify_phi_deg, false);
    bool all = true;
    for (const auto& [k, v] : checks.items()) all = all && v["met"].get<bool>();
    results["verification"] = {{"seeds", s.verify_seeds},
                               {"first_seed", fresh},
                               {"macro", macro_json(m)},
                               {"scatter", scatter_json(verify.per_seed)},
                               {"porosity", verify.porosity},
                               {"checks", checks},
                               {"all_met", all}};
    if (s.upscale > 1.0) {
      const Evaluation up = batch("upscaled", best, fresh, s.verify_seeds, s.upscale);
      nlohmann::json diff = macro_json(up.macro);
      const nlohmann::json base = macro_json(m);
      for (auto& [k, v] : diff.items()) v = v.get<double>() - base[k].get<double>();
      results["upscaling"] = {{"grain_size_factor", s.upscale},
                              {"macro", macro_json(up.macro)},
                              {"scatter", scatter_json(up.per_seed)},
                              {"difference", diff},
                              {"porosity", up.porosity}};
    }
  }
  results["porosity"] = verify.porosity;
  if (std::isfinite(g.unit_weight))
    results["unit_weight"] = density * s.gravity * (1.0 - verify.porosity);
  results["failed_runs"] = failed;

  if (study_root()) {
    MaterialFile mf;
    mf.name = s.name;
    mf.dimension = b.dimension;
    mf.material = micro_json(best, shear_ratio, density);
    mf.grain = b.grains.kinds.size() == 1 ? b.grains.kinds[0].shape : "";
    mf.radius_fuzz = b.radius_fuzz;
    mf.porosity = verify.porosity;
    mf.macro = macro_json(verify.macro);
    mf.macro["confining_stresses"] = b.confining_stresses;
    if (results.contains("unit_weight")) mf.macro["unit_weight"] = results["unit_weight"];
    mf.source = s.study.file;
    write_material_file(cat(opt.out_dir, "/material.toml"), mf);
    results["material_file"] = cat(opt.out_dir, "/material.toml");
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const nlohmann::json timing = study_timing(all_summaries, wall_s, exec);
  if (!study_root()) return {{"results", results}, {"timing", timing}};
  return write_run_summary(opt.out_dir, "calibrate", converged ? "completed" : "not_converged",
                           s.study.resolved, results, timing);
}

}  // namespace geodem
