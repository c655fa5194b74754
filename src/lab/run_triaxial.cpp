#include "lab/run_triaxial.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "base/error.hpp"
#include "base/text.hpp"
#include "contacts/bonds.hpp"
#include "io/output_files.hpp"
#include "io/progress.hpp"
#include "io/run_checkpoints.hpp"
#include "io/step_loop.hpp"
#include "lab/lab_controllers.hpp"
#include "lab/lab_domain.hpp"
#include "lab/lab_phases.hpp"
#include "lab/run_element_test.hpp"
#include "lab/soil_parameters.hpp"
#include "lab/triaxial_controllers.hpp"
#include "lab/triaxial_sample.hpp"
#include "lab/triaxial_test_state.hpp"
#include "measure/measurements.hpp"
#include "walls/lab_box.hpp"
#include "world/world_state.hpp"

namespace geodem {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The stages of the test, in order. A checkpoint records the stage and the loop
// counters within it; the run goes on from there on resuming.
enum class Phase : std::uint8_t {
  kCompaction,         // radius growth to the isotropic stress
  kFrictionReduction,  // friction lowered by steps to the target porosity
  kStabilisation,      // test friction back, stress held
  kConsolidation,      // this test's confining stress (first attempt)
  kConsolidationMore,  // stresses off target: up to compaction.max_steps more
  kCompression,        // strain-controlled axial loading
  kDone
};

template <int D>
struct Lab {
  using Vec = typename Dim<D>::Vec;
  static constexpr int kDim = D, kAxial = D - 1;
  const TriaxialSettings& s;
  const RunOptions& opt;
  const bool root;  // writes the outputs: one process, or rank 0 of a decomposed run
  World<D> w;
  World<D> prepared;    // the sample every test starts from
  LabDomain<D> domain;  // over the ranks of mpirun (docs/parallel.md)
  LabBox<D> box;
  Progress progress;
  HistoryCsv prep_csv, history;
  VtkSeries<D> vtk;
  RunCheckpoints checkpoints;
  std::vector<std::shared_ptr<Controller<D>>> servos;  // of the test under way

  // The run's own state, saved in checkpoints (visit_state).
  Phase phase = Phase::kCompaction;
  std::uint64_t stage_step = 0;    // steps into the current run_until
  double phi = 0.0;                // grain friction of the friction reduction (deg)
  std::uint8_t interval_open = 0;  // a friction-reduction interval is under way
  std::uint64_t total_steps = 0;
  nlohmann::json prep = nlohmann::json::object(), tests = nlohmann::json::array();
  std::uint64_t test = 0;  // index of the confining stress under test
  Shear<D> shear;
  ElementTest<D> element;  // the loading program of an element test

  Lab(const TriaxialSettings& settings, const RunOptions& options)
      : s(settings),
        opt(options),
        root(options.primary),
        progress(options.quiet || !options.primary),
        vtk(options.out_dir),
        checkpoints(lab_kind_name(settings.kind), D, settings.resolved, options.out_dir,
                    settings.checkpoint) {
    checkpoints.outputs({&prep_csv, &history});
    vtk.with_contacts(s.vtk_contacts);
  }

  double elapsed() const { return checkpoints.elapsed(); }
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
  double sigma3() const { return s.confining_stresses[test]; }

  template <class Archive>
  void visit_state(Archive& a) {
    a(phase), a(stage_step), a(phi), a(interval_open), a(total_steps), a(test);
    archive_json(a, prep), archive_json(a, tests);
    shear.visit(a);
    element.visit(a);
  }

  // The runner's part of a checkpoint and the world's (rank 0's whole domain when
  // decomposed: DomainWorldOnRank0).
  void save(StateWriter& runner, StateWriter& world) {
    visit_state(runner);
    runner(elapsed());
    runner(static_cast<std::uint64_t>(prep_csv.rows()));
    runner(static_cast<std::uint64_t>(history.rows()));
    vtk.save(runner);
    const bool tests_begun = phase >= Phase::kConsolidation;
    runner(static_cast<std::uint8_t>(tests_begun));
    domain.visit(runner, false);
    if (tests_begun) {
      StateWriter sample;
      save_world_state(sample, prepared);
      runner(sample.bytes());
      domain.visit(runner, true);
    }
    save_world_state(world, w);
  }

  // After a whole step: a checkpoint when due, and the stop on a signal. Checkpoints are
  // numbered by the run's step count: the world's restarts with each test's sample.
  // Closes a step of a loop (io/step_loop.hpp): a checkpoint when due; a signal stops the
  // run by throwing Interrupted, so the loop never goes on from here.
  bool after_step() {
    if (!domain) {
      checkpoints.after_step(total_steps, w.time,
                             [&](StateWriter& runner, StateWriter& world) { save(runner, world); });
      return false;
    }
    domain.after_step(
        w, phase >= Phase::kConsolidation ? &prepared : nullptr, checkpoints, total_steps, [&] {
          if (root)
            checkpoints.write_with(
                total_steps, w.time,
                [&](StateWriter& runner, StateWriter& world) { save(runner, world); });
        });
    return false;
  }

  // Steps with measurement every `every` steps; stops when `done()` holds on a
  // measured step or after max_steps. Returns false on reaching max_steps. Resumes
  // where a checkpoint left it (stage_step).
  template <typename Done>
  bool run_until(const std::string& stage, std::uint64_t max_steps, std::uint64_t every,
                 Done&& done) {
    const bool met = step_loop(
        w, total_steps, [&] { return stage_step < max_steps; },
        [&] { return ++stage_step % every == 0; },
        [&] {
          if (!w.measure_this_step) return false;
          const double unb = unbalanced_force_ratio(w);
          progress.update(stage, w.step, w.time, -1.0,
                          "mean stress " + format_sig(box.mean_stress(w)) + " Pa, porosity " +
                              format_sig(porosity()) + ", unbalanced " + format_sig(unb));
          return done(unb);
        },
        [&] { return after_step(); });
    stage_step = 0;
    return met;
  }

  // One row of preparation.csv; phase 1 compaction, 2 friction reduction, 3 stabilisation.
  void prep_row(double code) {
    const std::vector<double> row = {code,
                                     static_cast<double>(w.step),
                                     w.time,
                                     box.mean_stress(w),
                                     porosity(),
                                     grain_friction_deg(),
                                     unbalanced_force_ratio(w),
                                     coordination_number(w),
                                     radius_of_grain(w, 0)};
    if (root) prep_csv.row(row);
  }
  bool bonds() const { return s.bonds_create != "none"; }
  // A row of history.csv (rank 0 of a decomposed run writes it).
  void history_row(const std::vector<double>& row) {
    if (root) history.row(row);
  }

  void build() { box = build_triaxial_sample(w, s, opt.threads); }
  std::vector<std::string> history_columns() const {
    return s.kind == LabKind::kTriaxial ? triaxial_history_columns<D>(bonds(), s.undrained)
                                        : element_test_columns(s.kind);
  }

  void install_controllers(bool new_servos) {
    const TriaxialStage stage = phase <= Phase::kStabilisation ? TriaxialStage::kPreparation
                                : phase == Phase::kCompression ? TriaxialStage::kCompression
                                : phase == Phase::kDone        ? TriaxialStage::kDone
                                                               : TriaxialStage::kConsolidation;
    install_lab_controllers(*this, stage, new_servos);
  }

  void start() {
    prepare_output_dir(opt.out_dir);
    if (root) prep_csv.open(opt.out_dir + "/preparation.csv", triaxial_prep_columns());
    w.local_damping = s.compaction_damping;
    phase = Phase::kCompaction;
    install_controllers(false);
    domain.spread(w, nullptr, s, opt, false);
  }

  // Rebuilt from the scenario (build()), then the newest valid checkpoint's state.
  void resume() {
    const Checkpoint c = checkpoints.resume(s.file, {}, root);
    StateReader in(c.runner.data(), c.runner.size());
    visit_state(in);
    std::uint64_t prep_rows = 0, history_rows = 0;
    std::uint8_t tests_begun = 0;
    double wall_before = 0.0;
    in(wall_before), in(prep_rows), in(history_rows);
    vtk.restore(in, root);
    in(tests_begun);
    domain.visit(in, false);
    if (tests_begun) {
      std::string sample;
      in(sample);
      prepared = w;  // the scenario's walls and materials, no controllers
      StateReader sin(sample.data(), sample.size());
      load_world_state(sin, prepared);
      domain.visit(in, true);
    }
    install_controllers(true);
    StateReader win(c.world.data(), c.world.size());
    load_world_state(win, w);
    if (root) {
      prep_csv.resume_rows(opt.out_dir + "/preparation.csv", triaxial_prep_columns(), prep_rows);
      if (tests_begun)
        history.resume_rows(opt.out_dir + "/history.csv", history_columns(), history_rows);
    }
    checkpoints.resume_clock(wall_before);
    domain.spread(w, phase >= Phase::kConsolidation ? &prepared : nullptr, s, opt,
                  domain.decomposed);
  }

  // Holds at the compaction stress with a small unbalanced force (rows of `code`).
  bool stable_at_stress(double unb, double code) {
    prep_row(code);
    const double target = s.compaction_stress;
    return std::abs(box.mean_stress(w) - target) < s.stress_tolerance * target &&
           unb < s.unbalanced_tolerance;
  }

  // Radius growth to the isotropic stress.
  void compaction() {
    if (!run_until("compaction", s.max_compaction_steps, 200,
                   [&](double unb) { return stable_at_stress(unb, 1); }))
      throw std::runtime_error(
          "compaction did not reach the isotropic stress with unbalanced force < " +
          format_number(s.unbalanced_tolerance) + " in " + std::to_string(s.max_compaction_steps) +
          " steps; raise compaction.max_steps");
    prep["porosity_after_compaction"] = porosity();
    prep["compaction_steps"] = w.step;
    phi = grain_friction_deg();
    if (s.target_porosity > 0.0 && porosity() > s.target_porosity)
      phase = Phase::kFrictionReduction;
    else
      begin_stabilisation();
  }

  // Lower the friction by steps, holding the stress by radius growth, until the
  // porosity reaches the target (checked every 50 steps so as not to overshoot).
  void friction_reduction() {
    for (;;) {
      if (!interval_open) {
        if (phi < 1e-3) {
          prep["warning"] = "target porosity not reached with zero friction";
          break;
        }
        phi *= s.friction_factor;
        set_grain_friction_deg(phi);
        interval_open = 1;
      }
      const bool reached =
          run_until("friction reduction", static_cast<std::uint64_t>(s.friction_interval), 50,
                    [&](double) { return porosity() <= s.target_porosity; });
      prep_row(2);
      interval_open = 0;
      if (reached) break;
    }
    begin_stabilisation();
  }

  // Back to the test friction, then settle with the stress held.
  void begin_stabilisation() {
    prep["compaction_friction_deg"] = phi;
    set_grain_friction_deg(std::atan(s.grain.friction) / kDeg);
    phase = Phase::kStabilisation;
  }

  void stabilisation() {
    if (!run_until("stabilisation", s.max_compaction_steps, 200,
                   [&](double unb) { return stable_at_stress(unb, 3); }))
      throw std::runtime_error("the sample did not stabilise after the friction reduction");
    if (s.bonds_create == "after_compaction") prep["bonds"] = create_bonds(w, s.bond_gap_tolerance);
    prep["porosity"] = porosity();
    prep["mean_stress"] = box.mean_stress(w);
    prep["steps"] = w.step;
    w.controllers.clear();
    prepared = w;
    domain.keep_prepared(prepared);
    if (root) history.open(opt.out_dir + "/history.csv", history_columns());
    if (s.vtk) vtk.write(prepared);
    test = 0;
    begin_test();
  }

  // Isotropic re-consolidation of the prepared sample to this test's confining stress.
  void begin_test() {
    w = prepared;
    domain.start_from_prepared(w);
    w.local_damping = s.shear_damping;
    shear = Shear<D>{};
    phase = Phase::kConsolidation;
    install_controllers(true);
  }

  // Every axis at sigma3; in the shear box, the plate's axis (the sides are fixed).
  bool stresses_on_target() const {
    for (int k = s.kind == LabKind::kDirectShear ? kAxial : 0; k < D; ++k)
      if (std::abs(box.stress(w, k) - sigma3()) > s.stress_tolerance * sigma3()) return false;
    return true;
  }
  bool consolidated(double unb) const {
    return stresses_on_target() && unb < s.unbalanced_tolerance;
  }

  // A sample whose stresses are on target but whose unbalanced force stays just above
  // the tolerance (servo and damping jiggle) goes on after consolidation_max_steps, with
  // a warning in its results; one whose stresses are off keeps trying, up to max_steps.
  void consolidation() {
    auto done = [&](double unb) { return consolidated(unb); };
    if (phase == Phase::kConsolidationMore) {
      if (!run_until("consolidation", s.max_compaction_steps, 200, done))
        throw std::runtime_error("the sample did not consolidate to " + format_number(sigma3()) +
                                 " Pa");
      begin_compression();
      return;
    }
    if (run_until("consolidation", s.consolidation_max_steps, 200, done)) {
      begin_compression();
      return;
    }
    if (!stresses_on_target()) {
      phase = Phase::kConsolidationMore;
      return;
    }
    shear.warning = cat("unbalanced force ratio ", format_number(unbalanced_force_ratio(w)),
                        " above the tolerance after ", s.consolidation_max_steps,
                        " consolidation steps; the test went on");
    begin_compression();
  }

  void begin_compression() {
    if (s.bonds_create == "before_shear") shear.bonds_made = create_bonds(w, s.bond_gap_tolerance);
    shear.broken0 = broken_bond_count(w);
    shear.porosity0 = porosity();
    shear.height0 = box.size(w)[kAxial];
    shear.d0 = equivalent_diameter<D>(solid_volume(w) / static_cast<double>(body_count(w)));
    phase = Phase::kCompression;
    if (s.kind != LabKind::kTriaxial) {
      begin_element_test(*this);
      return;
    }
    install_controllers(false);
    shear.ref = box.size(w);
    shear.next_record = 0.0;
    shear.vtk_left = s.vtk_at_strains;
    std::sort(shear.vtk_left.begin(), shear.vtk_left.end(), std::greater<>());
    shear.curve.dimension = D;
    shear.eps = 0.0;
  }

  void compression() {
    if (s.kind != LabKind::kTriaxial) {
      run_element_test(*this);
      finish_test();
      return;
    }
    const double d_eps = s.max_axial_strain / s.history_points;
    Shear<D>& h = shear;
    step_loop(
        w, total_steps, [&] { return h.eps < s.max_axial_strain; },
        [&] {
          // Wall stresses come every step; the contact statistics (coordination, unbalanced
          // force) only on steps that may be recorded: those that reach the next record point.
          const double next_eps = h.eps + 2.0 * s.strain_rate * w.dt;
          return next_eps >= h.next_record || next_eps >= s.max_axial_strain;
        },
        [&] {
          h.eps = box.strain(w, kAxial, h.ref);
          if (w.measure_this_step && (h.eps >= h.next_record || h.eps >= s.max_axial_strain))
            record(d_eps);
          while (s.vtk && !h.vtk_left.empty() && h.eps >= h.vtk_left.back()) {
            vtk.write(w);
            h.vtk_left.pop_back();
          }
          return false;
        },
        [&] { return after_step(); });
    finish_test();
  }

  // One row of history.csv and one point of the curve.
  void record(double d_eps) {
    Shear<D>& h = shear;
    while (h.next_record <= h.eps) h.next_record += d_eps;
    const auto row = triaxial_history_row(h, box, w, s, test, sigma3(), bonds());
    history_row(row);
    progress.update("compression " + std::to_string(test + 1) + "/" +
                        std::to_string(s.confining_stresses.size()),
                    w.step, w.time, h.eps / s.max_axial_strain, "q " + format_sig(h.q_end) + " Pa",
                    (static_cast<double>(test) + h.eps / s.max_axial_strain) /
                        static_cast<double>(s.confining_stresses.size()));
  }

  // The test's results; then the next confining stress, or the end.
  void finish_test() {
    if (s.vtk) vtk.write(w);
    if (s.kind == LabKind::kTriaxial) {
      tests.push_back(test_results(shear, s, sigma3(), w, bonds()));
    } else {
      tests.push_back(element_test_results(*this));
      const bool shear_test = s.kind == LabKind::kSimpleShear || s.kind == LabKind::kDirectShear;
      tests.back()[shear_test ? "normal_stress" : "confining_stress"] = sigma3();
    }
    if (++test < s.confining_stresses.size()) {
      begin_test();
    } else {
      phase = Phase::kDone;
      w.controllers.clear();
    }
  }

  void run_phases() {
    for (;;) {
      switch (phase) {
        case Phase::kCompaction:
          compaction();
          break;
        case Phase::kFrictionReduction:
          friction_reduction();
          break;
        case Phase::kStabilisation:
          stabilisation();
          break;
        case Phase::kConsolidation:
        case Phase::kConsolidationMore:
          consolidation();
          break;
        case Phase::kCompression:
          compression();
          break;
        case Phase::kDone:
          return;
      }
    }
  }
};

template <int D>
nlohmann::json run(const TriaxialSettings& s, const RunOptions& opt) {
  Lab<D> lab(s, opt);
  const std::string kind = lab_kind_name(s.kind);
  naming_decomposition_errors(s.file, [&] { run_lab_phases(lab, kind, s.resolved, opt); });
  const nlohmann::json results = lab_run_results(s.kind, lab.prep, lab.tests);
  nlohmann::json timing = timing_json(lab.w, lab.elapsed(), lab.total_steps, opt.threads);
  if (lab.domain) lab.domain.add_timing(timing, lab.w, lab.total_steps);
  if (!opt.primary) return {{"results", results}};
  return write_run_summary(opt.out_dir, kind, "completed", s.resolved, results, timing);
}

}  // namespace

nlohmann::json run_triaxial(const TriaxialSettings& settings, const RunOptions& options) {
  return summarise_interruption(lab_kind_name(settings.kind), settings.resolved, options, [&] {
    return settings.dimension == 2 ? run<2>(settings, options) : run<3>(settings, options);
  });
}

}  // namespace geodem
