// kind = "calibrate" with an interface target (docs/studies.md, "Interface calibration"):
// the sheet's local interface friction delta that gives a macroscopic interface friction
// (the peak envelope of interface shear tests) equal to the target. A one-dimensional
// root search (SecantStep) over interface shear tests with fixed search seeds, then a
// verification with fresh seeds; writes material.toml: the soil with its calibrated
// interface.
#include <chrono>
#include <cmath>
#include <limits>

#include "base/text.hpp"
#include "io/material_file.hpp"
#include "io/output_files.hpp"
#include "lab/interface_parameters.hpp"
#include "study/calibration_search.hpp"
#include "study/linear_fit.hpp"
#include "study/run_studies.hpp"
#include "study/study_output.hpp"

namespace geodem {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct InterfaceMacro {
  InterfaceEnvelope peak, residual;
  std::vector<double> per_seed_friction, per_seed_adhesion;
  std::size_t runs = 0;
};

InterfaceEnvelope envelope_of(const std::vector<const nlohmann::json*>& tests, const char* key) {
  std::vector<double> sn, tau;
  for (const auto* t : tests) {
    sn.push_back((*t)["normal_stress"].get<double>());
    tau.push_back((*t)[key].get<double>());
  }
  return fit_interface_envelope(sn, tau);
}

InterfaceMacro evaluate(const std::vector<nlohmann::json>& summaries) {
  InterfaceMacro m;
  std::vector<const nlohmann::json*> all;
  for (const auto& s : summaries) {
    if (!run_completed(s)) continue;
    std::vector<const nlohmann::json*> mine;
    for (const auto& t : s["results"]["tests"]) mine.push_back(&t), all.push_back(&t);
    const InterfaceEnvelope e = envelope_of(mine, "peak_shear_stress");
    m.per_seed_friction.push_back(e.friction_deg);
    m.per_seed_adhesion.push_back(e.adhesion);
    ++m.runs;
  }
  if (all.empty()) throw std::runtime_error("no interface shear test of this step completed");
  m.peak = envelope_of(all, "peak_shear_stress");
  m.residual = envelope_of(all, "residual_shear_stress");
  return m;
}

nlohmann::json macro_json(const InterfaceMacro& m) {
  return {{"interface_friction_deg", m.peak.friction_deg},
          {"interface_adhesion", m.peak.adhesion},
          {"interface_friction_residual_deg", m.residual.friction_deg},
          {"interface_adhesion_residual", m.residual.adhesion},
          {"runs", m.runs}};
}

nlohmann::json material_json(const Material& m) {
  return {{"density", m.density},
          {"young", m.young},
          {"kt_over_kn", m.kt_over_kn},
          {"friction_deg", std::atan(m.friction) / kDeg},
          {"normal_cohesion", m.normal_cohesion},
          {"shear_cohesion", m.shear_cohesion},
          {"rolling_friction", m.rolling_friction}};
}

}  // namespace

nlohmann::json run_interface_calibrate(const InterfaceCalibrateSettings& s, const RunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const InterfaceShearSettings& b = s.check;
  StudyExecutor exec({opt.out_dir, s.file, opt.quiet, opt.threads});
  std::vector<nlohmann::json> all_summaries;
  nlohmann::json failed = nlohmann::json::array();
  auto batch = [&](const std::string& tag, double delta, std::uint64_t first_seed, int seeds) {
    std::vector<StudyRun> runs;
    for (int k = 0; k < seeds; ++k) {
      StudyRun r;
      const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
      r.id = cat(tag, "_seed", seed);
      r.scenario = s.base;
      set_key(r.scenario, "sheet.interface_friction_deg", delta);
      set_key(r.scenario, "seed", static_cast<std::int64_t>(seed));
      runs.push_back(std::move(r));
    }
    auto summaries = exec.run(runs, cat("interface calibration ", tag));
    for (auto& f : failed_runs(runs, summaries)) failed.push_back(std::move(f));
    all_summaries.insert(all_summaries.end(), summaries.begin(), summaries.end());
    return evaluate(summaries);
  };

  HistoryCsv csv;
  if (study_root())
    csv.open(cat(opt.out_dir, "/calibration.csv"),
             {"iteration", "local_friction_deg", "interface_friction_deg", "interface_adhesion",
              "miss"});
  // Macro friction rises with the local one about one for one (the rigid base gives
  // exactly delta): a secant search from there, steps of at most 10 deg.
  SecantStep step(1.0, 10.0, 1.0, 80.0);
  double delta = b.interface_friction_deg;
  double best = delta, best_miss = std::numeric_limits<double>::infinity();
  InterfaceMacro best_macro;
  nlohmann::json iterations = nlohmann::json::array();
  bool converged = false;
  for (int it = 0; it < s.max_iterations && !converged; ++it) {
    const InterfaceMacro m = batch(cat("iter", it), delta, b.seed, s.seeds);
    const double miss = std::abs(m.peak.friction_deg - s.target_friction_deg) / s.tol_deg;
    if (study_root())
      csv.row({static_cast<double>(it), delta, m.peak.friction_deg, m.peak.adhesion, miss});
    iterations.push_back({{"local_friction_deg", delta}, {"macro", macro_json(m)}, {"miss", miss}});
    if (miss < best_miss) best_miss = miss, best = delta, best_macro = m;
    converged = miss <= 1.0;
    if (!converged) delta = step.next(delta, m.peak.friction_deg, s.target_friction_deg);
  }

  nlohmann::json results;
  results["converged"] = converged;
  results["iterations"] = iterations;
  results["local_friction_deg"] = best;
  results["search"] = {{"macro", macro_json(best_macro)}, {"miss", best_miss}};
  InterfaceMacro verify = best_macro;
  if (s.verify_seeds > 0) {
    const std::uint64_t fresh = b.seed + 1000;
    verify = batch("verify", best, fresh, s.verify_seeds);
    nlohmann::json checks;
    const double err = verify.peak.friction_deg - s.target_friction_deg;
    checks["interface_friction_deg"] = {{"target", s.target_friction_deg},
                                        {"measured", verify.peak.friction_deg},
                                        {"error", err},
                                        {"tolerance", s.verify_deg},
                                        {"met", std::abs(err) <= s.verify_deg}};
    if (!std::isnan(s.target_adhesion)) {
      const double ea = verify.peak.adhesion - s.target_adhesion;
      checks["interface_adhesion"] = {{"target", s.target_adhesion},
                                      {"measured", verify.peak.adhesion},
                                      {"error", ea},
                                      {"tolerance", s.verify_adhesion},
                                      {"met", std::abs(ea) <= s.verify_adhesion}};
    }
    bool all = true;
    for (const auto& [k, v] : checks.items()) all = all && v["met"].get<bool>();
    results["verification"] = {
        {"seeds", s.verify_seeds},
        {"first_seed", fresh},
        {"macro", macro_json(verify)},
        {"scatter",
         {{"interface_friction_deg", standard_deviation(verify.per_seed_friction)},
          {"interface_adhesion", standard_deviation(verify.per_seed_adhesion)}}},
        {"per_seed_friction_deg", verify.per_seed_friction},
        {"checks", checks},
        {"all_met", all}};
  }
  results["failed_runs"] = failed;
  if (study_root()) {
    MaterialFile mf;
    mf.name = s.name;
    mf.dimension = 2;
    mf.material = material_json(b.soil);
    mf.grain = b.grains.kinds.size() == 1 ? b.grains.kinds[0].shape : "";
    mf.radius_fuzz = b.radius_fuzz;
    mf.interface = {{"local_friction_deg", best},
                    {"macro_friction_deg", verify.peak.friction_deg},
                    {"macro_adhesion", std::max(0.0, verify.peak.adhesion)},
                    {"sheet_element_length_over_radius", b.element_length / b.radius},
                    {"sheet_thickness_over_radius", b.thickness / b.radius},
                    {"sheet_bending_stiffness", b.bending},
                    {"sheet_stiffness_J", b.stiffness_J}};
    mf.macro = {{"interface_friction_residual_deg", verify.residual.friction_deg},
                {"interface_normal_stresses", b.normal_stress}};
    mf.source = s.file;
    write_material_file(cat(opt.out_dir, "/material.toml"), mf);
    results["material_file"] = cat(opt.out_dir, "/material.toml");
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const nlohmann::json timing = study_timing(all_summaries, wall_s, exec);
  if (!study_root()) return {{"results", results}, {"timing", timing}};
  return write_run_summary(opt.out_dir, "calibrate", converged ? "completed" : "not_converged",
                           s.resolved, results, timing);
}

}  // namespace geodem
