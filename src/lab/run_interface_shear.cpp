// The interface shear test (docs/lab_tests.md, "Interface shear"):
//   1. the soil is deposited by gravity in layers into a rigid box whose floor is the
//      sheet on its rigid base, and trimmed to the box height;
//   2. for each normal stress, from that deposit: the soil takes its own friction, a
//      plate is brought down and held at the normal stress less the soil's own weight
//      (so that the sheet carries the normal stress asked for), everything settles;
//      cohesive soils are bonded and settle again;
//   3. the sheet slides under the soil at a constant rate while the plate holds its
//      load; the shear and normal stresses on the sheet and the plate's rise are
//      recorded;
//   4. each test's peak, residual, stiffness and dilation, and the Mohr-Coulomb
//      envelope of the interface over the tests.
#include "lab/run_interface_shear.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "base/error.hpp"
#include "base/random.hpp"
#include "contacts/bonds.hpp"
#include "controllers/plate_servo.hpp"
#include "io/interrupt.hpp"
#include "io/output_files.hpp"
#include "io/progress.hpp"
#include "io/step_loop.hpp"
#include "lab/deposit_cache.hpp"
#include "lab/interface_box.hpp"
#include "lab/interface_parameters.hpp"
#include "lab/lab_domain.hpp"
#include "lab/lab_phases.hpp"
#include "lab/sheet_inertia.hpp"
#include "lab/soil_deposit.hpp"
#include "measure/measurements.hpp"
#include "world/step.hpp"
#include "world/world_editing.hpp"
#include "world/world_state.hpp"

namespace geodem {

namespace {

using Vec = Dim<2>::Vec;
constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<std::string> history_columns() {
  return {"test",           "normal_stress_target", "step",         "time",         "displacement",
          "shear_stress",   "normal_stress",        "stress_ratio", "plate_stress", "dilation",
          "kinetic_energy", "sheet_contacts"};
}

struct InterfaceShear {
  const InterfaceShearSettings& s;
  const RunOptions& opt;
  const bool root;  // writes the outputs: one process, or rank 0 of a decomposed run
  InterfaceBox box;
  World<2> w, deposit;
  // Over the ranks of mpirun (docs/parallel.md): spread once the first layer is dropped; the
  // deposit every test starts from keeps a copy of its domain (LabDomain::prepared).
  LabDomain<2> domain;
  Random rng;
  Progress progress;
  VtkSeries<2> vtk;
  HistoryCsv history;
  std::vector<ResolvedKind<2>> kinds;
  GrainAreas areas;  // sizes the deposited layers
  std::uint64_t total_steps = 0;
  std::size_t test = 0;  // index of the test in progress

  InterfaceShear(const InterfaceShearSettings& settings, const RunOptions& options)
      : s(settings),
        opt(options),
        root(options.primary),
        rng(settings.seed),
        progress(options.quiet || !options.primary),
        vtk(options.out_dir) {
    vtk.with_contacts(s.vtk_contacts);
  }

  bool soil_base() const { return s.base == "soil"; }
  // Height of the sheet's axis; the soil above it loads it.
  double sheet_axis() const { return (soil_base() ? s.lower_height : 0.0) + 0.5 * box.thickness; }

  // The whole deposit's grains (a decomposed run: every rank's own, counted over the ranks).
  std::size_t grain_count(const World<2>& world) const { return grain_and_clump_counts(world)[0]; }

  double fraction(double within) const {
    return (static_cast<double>(test) + within) / static_cast<double>(s.normal_stress.size() + 1);
  }

  void build() {
    w.materials = deposit_materials(s.soil, s.wall, s.interface_friction_deg);
    box.length = s.box_length;
    box.thickness = s.thickness;
    box.element_length = s.element_length;
    box.travel = s.max_displacement;
    box.margin = 4.0 * s.radius;
    box.mass_per_area = s.mass_per_area;
    box.stiffness_J = s.stiffness_J;
    box.bending = s.bending;
    box.wall_material = kDepositWalls;
    box.sheet_material = kDepositSheet;
    add_interface_box_walls(w, box);
    if (!soil_base()) add_rigid_base_sheet(w, box);
    configure_deposit_world(w, s, s.interface_friction_deg, s.dt_safety, s.dt_update_interval,
                            opt.threads);
    kinds = resolve_kinds<2>(s.grains);
    areas = grain_areas(kinds, s.radius, s.radius_fuzz);
  }

  // Steps until the soil is at rest (and the plate at its load, when there is one).
  void settle(const std::string& stage, const PlateServo<2>* plate) {
    const std::uint64_t every = 200;
    std::uint64_t k = 0;
    step_loop(
        w, total_steps, [] { return true; }, [&] { return ++k % every == 0; },
        [&] { return settled(stage, plate, k, every); },
        [&] { return domain.stop_on_signal(total_steps); });
  }

  // After a step of settle(): the progress line on measured steps; true when at rest.
  bool settled(const std::string& stage, const PlateServo<2>* plate, std::uint64_t k,
               std::uint64_t every) {
    if (!w.measure_this_step) return false;
    const double unb = unbalanced_force_ratio(w);
    double load_error = 0.0;
    if (plate) load_error = std::abs(plate->pressure(w) / plate->target() - 1.0);
    progress.update(
        stage, w.step, w.time, -1.0,
        "unbalanced " + format_sig(unb) + " (at rest below " + format_sig(s.settle_unbalanced) +
            ")" +
            (plate ? ", plate load off by " + format_sig(100.0 * load_error) + " % (within " +
                         format_sig(100.0 * s.consolidation_tolerance) + " %)"
                   : std::string()),
        fraction(0.0));
    if (k >= 5 * every && unb < s.settle_unbalanced && load_error < s.consolidation_tolerance &&
        !soil_moving(w, s.soil.density))
      return true;
    if (k >= s.max_settle_steps)
      throw std::runtime_error(stage + ": the soil did not come to rest (unbalanced force " +
                               format_number(unb) + ", plate load off by " +
                               format_number(100.0 * load_error) + " % after " + std::to_string(k) +
                               " steps); raise time.max_settle_steps or soil.settle_unbalanced");
    return false;
  }

  // Layers dropped from `base` up until the soil reaches `height`; trimmed there.
  void deposit_layers(double base, double height, const std::string& stage) {
    int layer = 0;
    for (;;) {
      const bool empty = grain_count(w) == 0;
      const double from = std::max(base, empty ? 0.0 : top_of_grains(w));
      if (!empty && top_of_grains(w) >= height) break;
      const double dense = std::min(s.layer_thickness, height - from + 2.0 * s.radius);
      // (a decomposed run: every rank drops the same layer and keeps its own grains of it)
      const std::size_t before = w.particles.size(), clumps_before = w.clumps.size();
      drop_layer(w, s, s.file, kinds, areas, rng, 0.0, s.box_length, from, dense);
      domain.grains_added(w, before, clumps_before, s.file, opt);
      settle(stage + " layer " + std::to_string(++layer), nullptr);
    }
    const auto& P = w.particles;
    remove_grains(
        w, grains_where(w, [&](std::size_t i) { return P.pos[i].y() + P.radius[i] > height; }));
  }

  // The soil: on the rigid base; or a lower layer, held still while the sheet is laid on
  // it and the upper layer deposited, then released.
  void deposit_soil() {
    if (!soil_base()) {
      deposit_layers(box.thickness, box.thickness + s.box_height, "deposit");
      settle("deposit", nullptr);
      return;
    }
    deposit_layers(0.0, s.lower_height, "lower soil");
    // The lower layer's grains are those of ids below `lower`: one process numbers them from
    // 0; a decomposed run keeps its ids (new grains take ids from next_id on).
    auto& P = w.particles;
    if (!domain)
      for (std::size_t i = 0; i < P.size(); ++i) P.id[i] = static_cast<std::uint32_t>(i);
    const std::size_t lower = domain ? P.next_id : P.size();
    hold_grains(w, std::vector<char>(P.size(), 1), true);
    add_pulled_sheet(w, box, sheet_axis(), s.box_length - 2.0 * s.radius);
    if (s.mass_scaling)
      scale_sheet_inertia(w, s.soil.young, s.stiffness_J, s.element_length, s.node_mass_factor);
    w.rebuild_needed = true;
    deposit_layers(s.lower_height + box.thickness, s.lower_height + box.thickness + s.box_height,
                   "upper soil");
    hold_grains(w, grains_where(w, [&](std::size_t i) { return P.id[i] < lower; }), false);
    settle("deposit", nullptr);
  }

  // The runner's part of a stored deposit (lab/deposit_cache.hpp): the random state and
  // the step count.
  template <class Archive>
  void visit_deposit(Archive& a) {
    std::string random = rng.state();
    a(random), a(total_steps);
    if (Archive::kLoading && !rng.set_state(random))
      throw CheckpointError("unreadable random state");
  }

  // Weight of the soil above the sheet per metre of the box (Pa on the sheet).
  double weight_on_sheet() const {
    if (!soil_base()) return grains_weight(w) / s.box_length;
    return grains_weight_above(w, sheet_axis()) / s.box_length;
  }

  nlohmann::json run_test(double sigma_n) {
    w = deposit;
    domain.start_from_prepared(w);
    const std::size_t plate_wall = add_loading_plate(w, box, top_of_grains(w) + 0.5 * s.radius);
    w.resolve_pair_laws();
    set_soil_friction(w, s.soil, s.soil.friction);
    set_interface_laws(w, std::tan(s.interface_friction_deg * kDeg));
    const double weight = weight_on_sheet();
    // The plate carries at least a fifth of the load: a plate barely touching a soil
    // that loads the sheet by its own weight does not control the normal stress.
    if (sigma_n - weight < 0.2 * sigma_n)
      throw InputError(s.file, 0, "shear.normal_stress",
                       "a normal stress of " + format_number(sigma_n) +
                           " Pa leaves the plate less than a fifth of it: the soil's own weight "
                           "loads the sheet with " +
                           format_number(weight) + " Pa; lower box.height or raise it");
    const std::string name =
        "test " + std::to_string(test + 1) + " (" + format_number(sigma_n / 1e3) + " kPa)";
    const double vmax = 0.05 * s.radius / w.dt;
    auto servo = std::make_shared<PlateServo<2>>(plate_wall, sigma_n - weight, vmax);
    w.controllers = {servo};
    settle(name + ": consolidation", servo.get());
    std::size_t bonds = 0;
    if (s.bonds) {
      bonds = create_bonds(w, s.bond_gap_tolerance);
      settle(name + ": bonded", servo.get());
    }
    if (s.vtk) vtk.write(w);

    // Shear: the sheet slides along +x under the soil (rigid base), or is pulled out
    // along -x by its clamp (soil base).
    w.local_damping = s.damping;
    auto& S = w.spars;
    if (soil_base())
      S.vel[0] = Vec(-s.rate, 0.0);
    else
      drive_sheet(w, s.rate);
    const double x0 = S.pos[0].x(), plate0 = w.walls[plate_wall].point.y();
    const double d_record = s.max_displacement / s.history_points;
    double next = d_record, u = 0.0, sum_t = 0.0, sum_n = 0.0, sum_p = 0.0, sum_target = 0.0;
    std::uint64_t steps = 0;
    const std::uint64_t start = w.step;
    InterfaceCurve c;
    double servo_error = 0.0, servo_error_sum = 0.0;
    step_loop(
        w, total_steps, [&] { return u < s.max_displacement; },
        [&] {
          const double u_next = std::abs(S.pos[0].x() - x0) + s.rate * w.dt;
          return u_next >= next || u_next >= s.max_displacement;
        },
        [&] {
          u = std::abs(S.pos[0].x() - x0);
          const double pressure = servo->pressure(w);
          if (soil_base()) {
            // Each face of the embedded length carries half the clamp's tension.
            const double embedded = std::max(S.pos[S.nodes() - 1].x(), s.radius);
            sum_t += S.tension[0] / (2.0 * embedded), sum_n += pressure + weight;
          } else {
            const InterfaceStresses st = interface_stresses(w, s.box_length);
            sum_t += st.shear, sum_n += st.normal;
          }
          sum_p += pressure, sum_target += servo->target(), ++steps;
          // Constant normal stiffness: the next step's target follows the plate's rise.
          if (s.normal_stiffness > 0.0)
            servo->set_target(std::max(
                0.0,
                sigma_n - weight + s.normal_stiffness * (w.walls[plate_wall].point.y() - plate0)));
          if (u + 1e-15 < next && u < s.max_displacement) return false;
          // A row holds the means since the previous one: the per-step values carry the
          // grains' vibrations.
          const double n = static_cast<double>(steps);
          const double tau = sum_t / n, sig = sum_n / n, pl = sum_p / n;
          // The plate's mean target over the row (constant without a normal stiffness).
          const double pl_target = s.normal_stiffness > 0.0 ? sum_target / n : servo->target();
          const double cns_target = s.normal_stiffness > 0.0 ? pl_target + weight : sigma_n;
          const double rise = w.walls[plate_wall].point.y() - plate0;
          const std::vector<double> row = {static_cast<double>(test),
                                           cns_target,
                                           static_cast<double>(w.step),
                                           w.time,
                                           u,
                                           tau,
                                           sig,
                                           sig > 0.0 ? tau / sig : 0.0,
                                           pl,
                                           rise,
                                           kinetic_energy(w),
                                           static_cast<double>(w.stats.spar_contacts)};
          if (root) history.row(row);
          c.displacement.push_back(u), c.shear.push_back(tau), c.normal.push_back(sig);
          c.dilation.push_back(rise);
          // Relative to the plate's load when shearing began: a target that a contracting
          // soil lowers towards 0 would make a relative error meaningless.
          const double servo_err = std::abs(pl - pl_target) / (sigma_n - weight);
          servo_error = std::max(servo_error, servo_err);
          servo_error_sum += servo_err;
          sum_t = sum_n = sum_p = sum_target = 0.0, steps = 0;
          while (next <= u + 1e-15) next += d_record;
          progress.update(name + ": shear", w.step, w.time, u / s.max_displacement,
                          "tau/sigma " + format_sig(sig > 0.0 ? tau / sig : 0.0),
                          fraction(u / s.max_displacement));
          return false;
        },
        [&] { return domain.stop_on_signal(total_steps); });
    if (s.vtk) vtk.write(w);
    const InterfaceTest t = interface_test(c, s.residual_from);
    return {{"normal_stress_target", sigma_n},
            {"normal_stress", t.normal_stress},
            {"normal_stress_at_peak", t.normal_at_peak},
            {"normal_stress_residual", t.residual_normal},
            {"peak_shear_stress", t.peak_shear},
            {"displacement_at_peak", t.displacement_at_peak},
            {"peak_stress_ratio", t.peak_ratio},
            {"peak_friction_deg", std::atan(t.peak_ratio) / kDeg},
            {"residual_shear_stress", t.residual_shear},
            {"residual_stress_ratio", t.residual_ratio},
            {"residual_friction_deg", std::atan(t.residual_ratio) / kDeg},
            {"shear_stiffness", t.shear_stiffness},
            {"dilation_max", t.dilation_max},
            {"dilation_end", t.dilation_end},
            {"dilation_angle_deg", t.dilation_angle_deg},
            {"plate_load", sigma_n - weight},
            {"soil_weight_stress", weight},
            {"servo_error_max", servo_error},
            {"servo_error_mean", servo_error_sum / static_cast<double>(c.displacement.size())},
            {"bonds", bonds},
            {"grains", grain_count(w)},
            {"shear_steps", w.step - start}};
  }
};

nlohmann::json envelope_json(const InterfaceEnvelope& e) {
  return {{"friction_deg", e.friction_deg},
          {"adhesion", e.adhesion},
          {"r2", e.r2},
          {"fitted", e.fitted}};
}

}  // namespace

namespace {
nlohmann::json run_tests(const InterfaceShearSettings& s, const RunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  InterfaceShear run(s, opt);
  prepare_output_dir(opt.out_dir);
  run.build();
  const DepositCache cache(s.deposit_cache,
                           LabDomain<2>::deposit_stage("interface_shear_deposit", opt), s.resolved,
                           {"shear.normal_stress", "output", "title", "seeds"});
  std::string cache_use;
  if (auto c = LabDomain<2>::load_deposit(cache, opt)) {
    // The pulled sheet is laid before the world's state goes back onto it.
    if (run.soil_base())
      add_pulled_sheet(run.w, run.box, run.sheet_axis(), s.box_length - 2.0 * s.radius);
    DepositCache::restore(*c, run.w, [&](StateReader& a) {
      run.visit_deposit(a);
      run.domain.load_deposit_domain(a, opt);
    });
    run.domain.spread_deposit(run.w, s.file, opt);
    cache_use = "loaded " + cache.path();
  } else {
    run.deposit_soil();
    if (cache.enabled())
      run.domain.store_deposit(run.w, run.root, opt, [&](auto&& visit_domain) {
        cache.store(run.w, [&](StateWriter& a) {
          run.visit_deposit(a);
          visit_domain(a);
        });
      });
    if (cache.enabled()) cache_use = "stored " + cache.path();
  }
  run.deposit = run.w;
  run.domain.keep_prepared(run.deposit);
  if (run.root) run.history.open(opt.out_dir + "/history.csv", history_columns());
  nlohmann::json tests = nlohmann::json::array();
  // Under a constant normal stiffness the normal stress moves during a test: each envelope
  // takes the normal stress of its own state (at the peak, over the residual range).
  const bool cns = s.normal_stiffness > 0.0;
  std::vector<double> sn, sn_residual, peak, residual;
  double stiffness_sum = 0.0;
  for (run.test = 0; run.test < s.normal_stress.size(); ++run.test) {
    tests.push_back(run.run_test(s.normal_stress[run.test]));
    const auto& t = tests.back();
    sn.push_back(t[cns ? "normal_stress_at_peak" : "normal_stress"].get<double>());
    sn_residual.push_back(t[cns ? "normal_stress_residual" : "normal_stress"].get<double>());
    peak.push_back(t["peak_shear_stress"].get<double>());
    residual.push_back(t["residual_shear_stress"].get<double>());
    stiffness_sum += t["shear_stiffness"].get<double>();
  }
  run.progress.finish();
  const InterfaceEnvelope ep = fit_interface_envelope(sn, peak);
  const InterfaceEnvelope er = fit_interface_envelope(sn_residual, residual);
  nlohmann::json results;
  results["local_interface_friction_deg"] = s.interface_friction_deg;
  results["normal_stiffness"] = s.normal_stiffness;
  results["interface_friction_peak_deg"] = ep.friction_deg;
  results["interface_adhesion_peak"] = ep.adhesion;
  results["interface_friction_residual_deg"] = er.friction_deg;
  results["interface_adhesion_residual"] = er.adhesion;
  results["peak_envelope"] = envelope_json(ep);
  results["residual_envelope"] = envelope_json(er);
  // The contract's names: the peak envelope, and the secant stiffness averaged over the
  // normal stresses (each test's own is in `tests`).
  results["interface_phi_deg"] = ep.friction_deg;
  results["interface_adhesion"] = ep.adhesion;
  results["interface_stiffness"] = stiffness_sum / static_cast<double>(sn.size());
  results["tests"] = tests;
  results["deposit_grains"] = run.grain_count(run.deposit);
  if (!cache_use.empty()) results["deposit_cache"] = cache_use;
  results["bodies"] = body_count(run.deposit);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json timing = timing_json(run.w, wall_s, run.total_steps, opt.threads);
  if (run.domain) run.domain.add_timing(timing, run.w, run.total_steps);
  if (!opt.primary) return {{"results", results}};
  return write_run_summary(opt.out_dir, "interface_shear", "completed", s.resolved, results,
                           timing);
}
}  // namespace

// A run stopped by a signal or an instability leaves a summary that says so (the history
// written so far is whole); it is run again from the start (no checkpoints).
nlohmann::json run_interface_shear(const InterfaceShearSettings& s, const RunOptions& opt) {
  try {
    return naming_decomposition_errors(s.file, [&] {
      return summarise_interruption("interface_shear", s.resolved, opt,
                                    [&] { return run_tests(s, opt); });
    });
  } catch (const InstabilityError& e) {
    const std::string why =
        std::string(e.what()) +
        " [interface shear tests take the automatic time step: time.safety (default 0.8); the "
        "soil's young]";
    if (opt.primary)
      write_stopped_summary(opt.out_dir, "interface_shear", s.resolved, "unstable", why, "",
                            opt.threads);
    throw InstabilityError(why);
  }
}

}  // namespace geodem
