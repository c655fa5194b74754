#include "study/study_settings.hpp"
#include "base/text.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace geodem {

namespace {

// Series and rate studies run one confining stress per test (calibration runs several).
void single_confining_stress(const StudyBase& b, const toml::table& root) {
  if (b.check.confining_stresses.size() != 1)
    throw InputError(b.file, source_line(root, "shear.confining_stress"), "shear.confining_stress",
                     "a study runs one confining stress per test; give a single value");
}

// The study file minus its own tables, read as a triaxial scenario.
StudyBase read_base(const toml::table& root, const std::string& file, const std::string& kind,
                    const std::vector<std::string>& own_tables) {
  StudyBase b;
  b.file = file;
  b.base = root;
  for (const auto& t : own_tables) b.base.erase(t);
  b.base.insert_or_assign("kind", "triaxial");
  b.plots = root["output"]["plots"].value_or(true);
  // The runs write no VTK or plots of their own; the study makes its figures.
  set_key(b.base, "output.vtk", false);
  set_key(b.base, "output.plots", false);
  try {
    b.check = read_triaxial(b.base, file);
  } catch (const InputError& e) {
    // The copy has lost its source lines: find the key's line in the file itself.
    if (e.line() != 0 || e.key().empty()) throw;
    throw InputError(e.file(), source_line(root, e.key()), e.key(), e.detail());
  }
  if (kind != "calibrate") single_confining_stress(b, root);
  b.resolved = b.check.resolved;
  b.resolved["kind"] = kind;
  b.resolved.erase("output");
  return b;
}

TableReader study_table(const toml::table& root, const std::string& file, nlohmann::json& out,
                        const std::string& name, const std::string& what) {
  TableReader r(root, "", file, &out);
  auto t = r.table(name);
  if (!t) r.fail(name, cat("missing [", name, "] table (", what, ")"));
  return *t;
}

std::string quantity(TableReader& t) {
  return t.choice("quantity", "peak_q", study_quantities());
}

}  // namespace

SeriesSettings read_series(const toml::table& root, const std::string& file) {
  SeriesSettings s;
  s.study = read_base(root, file, "series", {"series"});
  TableReader t = study_table(root, file, s.study.resolved, "series", "counts, seeds");
  const std::vector<double> counts = t.numbers("counts", std::vector<double>{}, 2);
  std::set<std::size_t> distinct;
  for (double c : counts) {
    if (!(c >= 2.0 && c <= 5e7 && c == std::floor(c)))
      t.fail("counts", "expected whole grain counts from 2 to 50,000,000");
    distinct.insert(static_cast<std::size_t>(c));
  }
  if (distinct.size() < 2) t.fail("counts", "expected two different grain counts or more");
  s.counts.assign(distinct.begin(), distinct.end());
  s.seeds = static_cast<int>(t.integer("seeds", 5, 1, 100000));
  s.tolerance = t.in_range("tolerance", 0.05, 1e-6, 1.0);
  s.with_scatter = t.choice("criterion", "bias", {"bias", "bias_and_scatter"}) != "bias";
  s.quantity = quantity(t);
  t.finish();
  return s;
}

RateStudySettings read_rate_study(const toml::table& root, const std::string& file) {
  RateStudySettings s;
  s.study = read_base(root, file, "rate_study", {"rate_study"});
  TableReader t = study_table(root, file, s.study.resolved, "rate_study", "strain_rates, damping");
  s.strain_rates = t.numbers("strain_rates", std::vector<double>{}, 1);
  for (double r : s.strain_rates)
    if (!(r > 0.0 && r <= 100.0)) t.fail("strain_rates", "expected strain rates in (0, 100] 1/s");
  s.damping = t.numbers("damping", {s.study.check.shear_damping}, 1);
  for (double d : s.damping)
    if (!(d >= 0.0 && d < 1.0)) t.fail("damping", "expected damping coefficients in [0, 1)");
  std::set<double> products;
  for (double r : s.strain_rates)
    for (double d : s.damping) products.insert(r * d);
  if (products.size() < 2)
    t.fail("strain_rates", "the fit needs two different values of damping x strain rate or more");
  s.seeds = static_cast<int>(t.integer("seeds", 1, 1, 100000));
  s.tolerance = t.in_range("tolerance", 0.02, 1e-6, 1.0);
  s.quantity = quantity(t);
  t.finish();
  return s;
}

CalibrateSettings read_calibrate(const toml::table& root, const std::string& file) {
  CalibrateSettings s;
  s.study = read_base(root, file, "calibrate", {"calibrate", "targets"});
  const TriaxialSettings& b = s.study.check;
  if (b.confining_stresses.size() < 2 && b.grain.normal_cohesion + b.grain.shear_cohesion > 0.0)
    throw InputError(file, 0, "shear.confining_stress",
                     "a cohesive soil needs two confining stresses or more (Mohr-Coulomb fit)");
  {
    TableReader t = study_table(root, file, s.study.resolved, "targets", "phi_peak_deg, cohesion");
    CalibrationTargets& g = s.targets;
    g.phi_peak_deg = t.in_range("phi_peak_deg", 30.0, 1.0, 70.0);
    if (!t.has("phi_peak_deg")) t.fail("phi_peak_deg", "the peak friction angle is required");
    g.cohesion = t.non_negative("cohesion", 0.0);
    if (t.has("young_modulus")) g.young_modulus = t.positive("young_modulus", 1e7);
    if (t.has("poisson_ratio")) g.poisson_ratio = t.in_range("poisson_ratio", 0.3, 0.01, 0.7);
    if (t.has("phi_residual_deg"))
      g.phi_residual_deg = t.in_range("phi_residual_deg", 30.0, 1.0, 70.0);
    if (t.has("unit_weight")) g.unit_weight = t.positive("unit_weight", 18e3);
    t.finish();
    if (g.cohesion > 0.0 && b.confining_stresses.size() < 2)
      throw InputError(file, 0, "shear.confining_stress",
                       "a cohesion target needs two confining stresses or more");
    if (g.cohesion > 0.0 && b.grain.normal_cohesion + b.grain.shear_cohesion <= 0.0)
      throw InputError(file, 0, "material.normal_cohesion",
                       "a cohesion target needs a starting bond strength (normal_cohesion and "
                       "shear_cohesion > 0)");
  }
  TableReader c(root, "", file, &s.study.resolved);
  if (auto t = c.table("calibrate")) {
    s.name = t->string("name", "calibrated");
    s.seeds = static_cast<int>(t->integer("seeds", 2, 1, 1000));
    s.verify_seeds = static_cast<int>(t->integer("verify_seeds", 3, 0, 1000));
    s.max_iterations = static_cast<int>(t->integer("max_iterations", 8, 1, 100));
    s.tol_phi_deg = t->in_range("tolerance_phi_deg", 0.5, 0.01, 10.0);
    s.tol_cohesion = t->in_range("tolerance_cohesion", 500.0, 1.0, 1e9);
    s.tol_young = t->in_range("tolerance_young", 0.05, 1e-3, 1.0);
    s.tol_poisson = t->in_range("tolerance_poisson", 0.02, 1e-3, 0.5);
    s.verify_phi_deg = t->in_range("verify_phi_deg", 1.5, 0.01, 10.0);
    s.verify_cohesion = t->in_range("verify_cohesion", 2000.0, 1.0, 1e9);
    s.verify_young = t->in_range("verify_young", 0.15, 1e-3, 1.0);
    s.verify_poisson = t->in_range("verify_poisson", 0.05, 1e-3, 0.5);
    s.upscale = t->in_range("upscale", 2.0, 1.0, 100.0);
    s.gravity = t->in_range("gravity", 9.81, 0.01, 100.0);
    t->finish();
  }
  return s;
}

bool is_interface_calibration(const toml::table& root) {
  const toml::table* t = root["targets"].as_table();
  return t && t->contains("interface_friction_deg");
}

InterfaceCalibrateSettings read_interface_calibrate(const toml::table& root,
                                                    const std::string& file) {
  InterfaceCalibrateSettings s;
  s.file = file;
  s.base = root;
  s.base.erase("targets");
  s.base.erase("calibrate");
  s.base.insert_or_assign("kind", "interface_shear");
  s.plots = root["output"]["plots"].value_or(true);
  set_key(s.base, "output.vtk", false);
  set_key(s.base, "output.plots", false);
  try {
    s.check = read_interface_shear(s.base, file);
  } catch (const InputError& e) {
    if (e.line() != 0 || e.key().empty()) throw;
    throw InputError(e.file(), source_line(root, e.key()), e.key(), e.detail());
  }
  s.resolved = s.check.resolved;
  s.resolved["kind"] = "calibrate";
  s.resolved.erase("output");
  {
    TableReader t = study_table(root, file, s.resolved, "targets", "interface_friction_deg");
    s.target_friction_deg = t.in_range("interface_friction_deg", 34.0, 1.0, 80.0);
    if (t.has("interface_adhesion")) s.target_adhesion = t.non_negative("interface_adhesion", 0.0);
    t.finish();
  }
  if (s.check.normal_stress.size() < 2 && !std::isnan(s.target_adhesion))
    throw InputError(file, source_line(root, "shear.normal_stress"), "shear.normal_stress",
                     "an adhesion target needs two normal stresses or more (envelope fit)");
  TableReader c(root, "", file, &s.resolved);
  if (auto t = c.table("calibrate")) {
    s.name = t->string("name", "calibrated");
    s.seeds = static_cast<int>(t->integer("seeds", 2, 1, 1000));
    s.verify_seeds = static_cast<int>(t->integer("verify_seeds", 3, 0, 1000));
    s.max_iterations = static_cast<int>(t->integer("max_iterations", 8, 1, 100));
    s.tol_deg = t->in_range("tolerance_deg", 0.5, 0.01, 10.0);
    s.verify_deg = t->in_range("verify_deg", 1.5, 0.01, 10.0);
    s.verify_adhesion = t->in_range("verify_adhesion", 2000.0, 1.0, 1e9);
    t->finish();
  }
  return s;
}

}  // namespace geodem
