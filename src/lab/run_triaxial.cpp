#include "lab/run_triaxial.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "clumps/grain_mix.hpp"
#include "contacts/bonds.hpp"
#include "controllers/axial_strain_rate.hpp"
#include "controllers/radius_growth.hpp"
#include "controllers/stress_servo.hpp"
#include "core/error.hpp"
#include "core/random.hpp"
#include "core/step.hpp"
#include "core/text.hpp"
#include "io/interrupt.hpp"
#include "io/output_files.hpp"
#include "io/progress.hpp"
#include "lab/lab_box.hpp"
#include "lab/soil_parameters.hpp"
#include "measure/measurements.hpp"
#include "scene/random_cloud.hpp"

namespace geodem {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Diameter of the disc (2D) or sphere (3D) of volume v: the grain size d0 of a sample.
template <int D>
double equivalent_diameter(double v) {
  return D == 2 ? 2.0 * std::sqrt(v / std::numbers::pi) : std::cbrt(6.0 * v / std::numbers::pi);
}

template <int D>
struct Lab {
  using Vec = typename Dim<D>::Vec;
  const TriaxialSettings& s;
  const RunOptions& opt;
  World<D> w;
  LabBox<D> box;
  Progress progress;
  HistoryCsv prep_csv;
  std::uint64_t total_steps = 0;
  double wall_s = 0.0;

  Lab(const TriaxialSettings& settings, const RunOptions& options)
      : s(settings), opt(options), progress(options.quiet) {}

  double porosity() const { return 1.0 - solid_volume(w) / box.volume(w); }
  double grain_friction_deg() const { return std::atan(w.pair_law(0, 0).mu) / kDeg; }
  // Sets the grain-grain friction (entry (0, 0) of the pair table). Rolling and twisting
  // friction follow in proportion, so that the friction reduction of the compaction
  // lowers all of them together and the test values come back with the friction.
  void set_grain_friction_deg(double deg) {
    PairLaw& law = w.pair_laws[0];
    law.mu = std::tan(deg * kDeg);
    const double ratio = s.grain.friction > 0.0 ? law.mu / s.grain.friction : 1.0;
    law.roll_mu = s.grain.rolling_friction * ratio;
    law.twist_mu = s.grain.twisting_friction * ratio;
  }

  // Steps with measurement every `every` steps; stops when `done()` holds on a
  // measured step or after max_steps. Returns false on reaching max_steps.
  template <typename Done>
  bool run_until(const std::string& stage, std::uint64_t max_steps, std::uint64_t every,
                 Done&& done, double fraction_base = 0.0) {
    for (std::uint64_t k = 1; k <= max_steps; ++k) {
      w.measure_this_step = k % every == 0;
      step(w);
      stop_if_interrupted();
      ++total_steps;
      if (w.measure_this_step) {
        const double unb = unbalanced_force_ratio(w);
        progress.update(stage, w.step, w.time, fraction_base,
                        "mean stress " + format_number(box.mean_stress(w)) + " Pa, porosity " +
                            format_number(porosity()) + ", unbalanced " + format_number(unb));
        if (done(unb)) return true;
      }
    }
    return false;
  }

  // One row of preparation.csv; phase 1 compaction, 2 friction reduction, 3 stabilisation.
  void prep_row(double phase) {
    prep_csv.row({phase, static_cast<double>(w.step), w.time, box.mean_stress(w), porosity(),
                  grain_friction_deg(), unbalanced_force_ratio(w), coordination_number(w),
                  w.particles.radius.empty() ? 0.0 : w.particles.radius[0]});
  }

  void build() {
    w.materials = {s.grain, s.wall};
    Vec size;
    for (int k = 0; k < D; ++k) size[k] = s.box[static_cast<std::size_t>(k)];
    box = LabBox<D>::add_to(w, Vec::Zero(), size, 1);
    w.resolve_pair_laws();
    Random rng(s.seed);
    try {
      if (s.grains.round_only()) {
        const double mean =
            mean_radius_for_porosity<D>(size.prod(), s.count, s.initial_porosity, s.radius_fuzz);
        const auto grains = random_cloud<D>(Vec::Zero(), size, s.count, mean, s.radius_fuzz, rng);
        w.particles.reserve(grains.size());
        for (const auto& g : grains) w.particles.add(g.centre, g.radius, s.grain.density, 0);
      } else {
        add_random_grains<D>(w, resolve_kinds<D>(s.grains), Vec::Zero(), size, s.count,
                             s.initial_porosity, s.radius_fuzz, s.grain.density, 0, rng);
      }
    } catch (const std::runtime_error& e) {
      throw InputError(s.file, 0, "sample.initial_porosity", e.what());
    }
    w.auto_dt = true;
    w.dt_safety = s.dt_safety;
    w.dt_update_interval = s.dt_update_interval;
    w.sort_interval = 10;
    w.threads = opt.threads;
  }

  // Radius growth to the isotropic stress; then friction reduction to the target porosity.
  nlohmann::json prepare() {
    prep_csv.open(opt.out_dir + "/preparation.csv",
                  {"phase", "step", "time", "mean_stress", "porosity", "friction_deg", "unbalanced",
                   "coordination", "radius_0"});
    w.local_damping = s.compaction_damping;
    auto growth = std::make_shared<RadiusGrowth<D>>(box, s.compaction_stress, s.max_multiplier,
                                                    s.final_max_multiplier);
    w.controllers = {growth};
    const double target = s.compaction_stress;
    auto stable = [&](double unb) {
      prep_row(1);
      return std::abs(box.mean_stress(w) - target) < s.stress_tolerance * target &&
             unb < s.unbalanced_tolerance;
    };
    if (!run_until("compaction", s.max_compaction_steps, 200, stable, 0.0))
      throw std::runtime_error(
          "compaction did not reach the isotropic stress with unbalanced force < " +
          format_number(s.unbalanced_tolerance) + " in " + std::to_string(s.max_compaction_steps) +
          " steps; raise compaction.max_steps");
    nlohmann::json prep;
    prep["porosity_after_compaction"] = porosity();
    prep["compaction_steps"] = w.step;
    double phi = grain_friction_deg();
    if (s.target_porosity > 0.0) {
      // Lower the friction by steps, holding the stress by radius growth, until the
      // porosity reaches the target (checked every 50 steps so as not to overshoot).
      bool reached = porosity() <= s.target_porosity;
      while (!reached) {
        if (phi < 1e-3) {
          prep["warning"] = "target porosity not reached with zero friction";
          break;
        }
        phi *= s.friction_factor;
        set_grain_friction_deg(phi);
        reached = run_until("friction reduction", static_cast<std::uint64_t>(s.friction_interval),
                            50, [&](double) { return porosity() <= s.target_porosity; });
        prep_row(2);
      }
    }
    prep["compaction_friction_deg"] = phi;
    // Back to the test friction, then settle with the stress held.
    set_grain_friction_deg(std::atan(s.grain.friction) / kDeg);
    if (!run_until("stabilisation", s.max_compaction_steps, 200, [&](double unb) {
          prep_row(3);
          return std::abs(box.mean_stress(w) - target) < s.stress_tolerance * target &&
                 unb < s.unbalanced_tolerance;
        }))
      throw std::runtime_error("the sample did not stabilise after the friction reduction");
    if (s.bonds_create == "after_compaction") prep["bonds"] = create_bonds(w, s.bond_gap_tolerance);
    prep["porosity"] = porosity();
    prep["mean_stress"] = box.mean_stress(w);
    prep["steps"] = w.step;
    w.controllers.clear();
    return prep;
  }
};

template <int D>
nlohmann::json run(const TriaxialSettings& s, const RunOptions& opt) {
  using Vec = typename Dim<D>::Vec;
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  prepare_output_dir(opt.out_dir);
  Lab<D> lab(s, opt);
  lab.build();
  nlohmann::json results;
  results["preparation"] = lab.prepare();
  const World<D> prepared = lab.w;
  const int axial = D - 1;
  const bool several = s.confining_stresses.size() > 1;

  std::vector<std::string> cols = {"test",  "step", "time", "axial_strain", "volumetric_strain",
                                   "sigma1"};
  if (D == 3) cols.push_back("sigma2");
  for (const char* c : {"sigma3", "p", "q", "porosity", "coordination", "unbalanced"})
    cols.push_back(c);
  const bool bonds = s.bonds_create != "none";
  if (bonds) cols.insert(cols.end(), {"bonds", "broken_bonds"});
  HistoryCsv history;
  history.open(opt.out_dir + "/history.csv", cols);
  VtkSeries<D> vtk(opt.out_dir);
  if (s.vtk) vtk.write(prepared);

  nlohmann::json tests = nlohmann::json::array();
  std::vector<double> s1_peaks, s3_peaks;
  for (std::size_t t = 0; t < s.confining_stresses.size(); ++t) {
    const double sigma3 = s.confining_stresses[t];
    lab.w = prepared;
    World<D>& w = lab.w;
    w.local_damping = s.shear_damping;
    // Isotropic re-consolidation to this test's confining stress.
    std::vector<std::shared_ptr<StressServo<D>>> servos;
    for (int k = 0; k < D; ++k)
      servos.push_back(std::make_shared<StressServo<D>>(lab.box, k, sigma3, s.servo_gain));
    w.controllers.assign(servos.begin(), servos.end());
    auto consolidated = [&](double unb) {
      for (int k = 0; k < D; ++k)
        if (std::abs(lab.box.stress(w, k) - sigma3) > s.stress_tolerance * sigma3) return false;
      return unb < s.unbalanced_tolerance;
    };
    // A sample whose stresses are on target but whose unbalanced force stays just above
    // the tolerance (servo and damping jiggle) goes on after consolidation_max_steps, with
    // a warning in its results; one whose stresses are off keeps trying, up to max_steps.
    std::string consolidation_warning;
    if (!lab.run_until("consolidation", s.consolidation_max_steps, 200, consolidated)) {
      bool on_target = true;
      for (int k = 0; k < D; ++k)
        on_target =
            on_target && std::abs(lab.box.stress(w, k) - sigma3) <= s.stress_tolerance * sigma3;
      if (on_target) {
        consolidation_warning =
            cat("unbalanced force ratio ", format_number(unbalanced_force_ratio(w)),
                " above the tolerance after ", s.consolidation_max_steps,
                " consolidation steps; the test went on");
      } else if (!lab.run_until("consolidation", s.max_compaction_steps, 200, consolidated)) {
        throw std::runtime_error("the sample did not consolidate to " + format_number(sigma3) +
                                 " Pa");
      }
    }
    std::size_t bonds_made = 0;
    if (s.bonds_create == "before_shear") bonds_made = create_bonds(w, s.bond_gap_tolerance);
    const std::uint64_t broken0 = w.broken_bonds;
    const double porosity0 = lab.porosity();
    const double height0 = lab.box.size(w)[axial];
    const double d0 = equivalent_diameter<D>(solid_volume(w) / static_cast<double>(body_count(w)));
    // Compression: axial wall strain-controlled, lateral walls servo-controlled.
    w.controllers.clear();
    for (int k = 0; k < D - 1; ++k) w.controllers.push_back(servos[static_cast<std::size_t>(k)]);
    w.controllers.push_back(std::make_shared<AxialStrainRate<D>>(lab.box, axial, s.strain_rate));
    const Vec ref = lab.box.size(w);
    const double d_eps = s.max_axial_strain / s.history_points;
    double next_record = 0.0;
    std::vector<double> vtk_left = s.vtk_at_strains;
    std::sort(vtk_left.begin(), vtk_left.end(), std::greater<>());
    CompressionCurve curve;
    curve.dimension = D;
    double eps = 0.0;
    while (eps < s.max_axial_strain) {
      // Wall stresses come every step; the contact statistics (coordination, unbalanced
      // force) only on steps that may be recorded: those that reach the next record point.
      const double next_eps = eps + 2.0 * s.strain_rate * w.dt;
      w.measure_this_step = next_eps >= next_record || next_eps >= s.max_axial_strain;
      step(w);
      stop_if_interrupted();
      ++lab.total_steps;
      eps = lab.box.strain(w, axial, ref);
      if (w.measure_this_step && (eps >= next_record || eps >= s.max_axial_strain)) {
        while (next_record <= eps) next_record += d_eps;
        double lat[2] = {lab.box.stress(w, 0), D == 3 ? lab.box.stress(w, 1) : 0.0};
        const double s1 = lab.box.stress(w, axial);
        const double s2 = D == 3 ? std::max(lat[0], lat[1]) : lat[0];
        const double s3 = D == 3 ? std::min(lat[0], lat[1]) : lat[0];
        const double ev = lab.box.volumetric_strain(w, ref);
        const double p = D == 3 ? (s1 + s2 + s3) / 3.0 : 0.5 * (s1 + s3);
        std::vector<double> row = {
            static_cast<double>(t), static_cast<double>(w.step), w.time, eps, ev, s1};
        if (D == 3) row.push_back(s2);
        for (double v :
             {s3, p, s1 - s3, lab.porosity(), coordination_number(w), unbalanced_force_ratio(w)})
          row.push_back(v);
        if (bonds) {
          row.push_back(static_cast<double>(intact_bonds(w)));
          row.push_back(static_cast<double>(w.broken_bonds - broken0));
        }
        history.row(row);
        curve.axial_strain.push_back(eps);
        curve.volumetric_strain.push_back(ev);
        curve.sigma1.push_back(s1);
        curve.sigma3.push_back(s3);
        lab.progress.update("compression " + std::to_string(t + 1) + "/" +
                                std::to_string(s.confining_stresses.size()),
                            w.step, w.time, eps / s.max_axial_strain,
                            "q " + format_number(s1 - s3) + " Pa");
      }
      while (s.vtk && !vtk_left.empty() && eps >= vtk_left.back()) {
        vtk.write(w);
        vtk_left.pop_back();
      }
    }
    if (s.vtk) vtk.write(w);
    const SoilParameters sp = soil_parameters(curve);
    nlohmann::json r;
    r["confining_stress"] = sigma3;
    r["porosity_initial"] = porosity0;
    r["peak_q"] = sp.peak_q;
    r["axial_strain_at_peak"] = sp.axial_strain_at_peak;
    r["phi_peak_deg"] = sp.phi_peak_deg;
    r["phi_residual_deg"] = sp.phi_residual_deg;
    r["young_modulus"] = sp.young_modulus;
    r["poisson_ratio"] = sp.poisson_ratio;
    r["dilatancy_deg"] = sp.dilatancy_deg;
    // Peak principal stresses, for envelopes pooled over several runs (studies).
    std::size_t ip = 0;
    for (std::size_t i = 0; i < curve.sigma1.size(); ++i)
      if (curve.sigma1[i] - curve.sigma3[i] > curve.sigma1[ip] - curve.sigma3[ip]) ip = i;
    r["sigma1_peak"] = curve.sigma1[ip];
    r["sigma3_peak"] = curve.sigma3[ip];
    // Size and rate measures of the representativeness and rate studies.
    r["grain_size_d0"] = d0;
    r["sample_height"] = height0;
    r["d0_over_L"] = d0 / height0;
    r["inertial_number"] = s.strain_rate * d0 * std::sqrt(s.grain.density / sigma3);
    r["steps"] = w.step;
    if (bonds) {
      r["bonds_at_start"] = s.bonds_create == "before_shear"
                                ? bonds_made
                                : intact_bonds(w) + (w.broken_bonds - broken0);
      r["bonds_broken"] = w.broken_bonds - broken0;
    }
    r["grains"] = body_count(w);
    if (!consolidation_warning.empty()) r["warning"] = consolidation_warning;
    tests.push_back(r);
    s1_peaks.push_back(curve.sigma1[ip]);
    s3_peaks.push_back(curve.sigma3[ip]);
  }
  lab.progress.finish();
  results["tests"] = tests;
  if (tests.size() == 1)
    for (auto& [k, v] : tests[0].items()) results[k] = v;  // the contract's flat keys
  if (several) {
    const MohrCoulomb mc = fit_mohr_coulomb(s1_peaks, s3_peaks);
    results["mohr_coulomb"] = {{"cohesion", mc.cohesion}, {"phi_deg", mc.phi_deg}};
  }
  const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const nlohmann::json summary =
      write_run_summary(opt.out_dir, "triaxial", "completed", s.resolved, results,
                        timing_json(lab.w, wall_s, lab.total_steps, opt.threads));
  return summary;
}

}  // namespace

nlohmann::json run_triaxial(const TriaxialSettings& settings, const RunOptions& options) {
  try {
    return settings.dimension == 2 ? run<2>(settings, options) : run<3>(settings, options);
  } catch (const Interrupted& i) {
    write_interrupted_summary(options.out_dir, "triaxial", settings.resolved, i.signal,
                              options.threads);
    throw;
  }
}

}  // namespace geodem
