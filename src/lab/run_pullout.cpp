// The pull-out test of a geosynthetic anchorage (docs/lab_tests.md, "Pull-out"):
//   1. foundation: gravity deposition in layers in a rigid box, trimmed flat at the
//      run-out level; the trench (L or V) is excavated;
//   2. the sheet is laid along the anchor's shape; the foundation is held still while
//      the trench and the cover are filled by deposition in layers and trimmed flat;
//   3. optional surcharge plate; the foundation is released and everything settles;
//      cohesive soils are bonded;
//   4. the free end is pulled horizontally at a constant rate; the tension there, the
//      tension profile and the displacement of the anchoring soil are recorded.
#include "lab/run_pullout.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "base/error.hpp"
#include "base/random.hpp"
#include "contacts/bonds.hpp"
#include "controllers/surface_pressure.hpp"
#include "io/output_files.hpp"
#include "io/progress.hpp"
#include "io/run_checkpoints.hpp"
#include "io/step_loop.hpp"
#include "lab/anchorage.hpp"
#include "lab/anchorage_mechanism.hpp"
#include "lab/deposit_cache.hpp"
#include "lab/lab_phases.hpp"
#include "lab/pullout_results.hpp"
#include "lab/sheet_inertia.hpp"
#include "lab/soil_deposit.hpp"
#include "measure/measurements.hpp"
#include "world/world_editing.hpp"
#include "world/world_state.hpp"

namespace geodem {

namespace {

using Vec = Dim<2>::Vec;
constexpr double kDeg = std::numbers::pi / 180.0;
enum : std::uint16_t { kSoil = kDepositSoil, kWalls = kDepositWalls, kSheet = kDepositSheet };
constexpr std::size_t kFrontWall = 1;  // in World::walls (floor, front, back)

// The stages of the test, in order. A checkpoint records the stage and the loop
// counters within it; the run goes on from there on resuming.
enum class Phase : std::uint8_t {
  kFoundation,     // deposition of the foundation in layers
  kTrenchFill,     // the sheet laid, the foundation held: the trench filled
  kCover,          // the cover deposited
  kConsolidation,  // foundation released, surcharge placed: everything settles
  kSpillSettle,    // grains spilled off a free face removed: settle again
  kBonded,         // cohesive soils: settle with the bonds
  kPull,           // the free end pulled at a constant rate
  kDone
};

struct Pullout {
  const PulloutSettings& s;
  const RunOptions& opt;
  World<2> w;
  Progress progress;
  Random rng;
  std::vector<ResolvedKind<2>> kinds;
  GrainAreas areas;  // sizes the deposited layers
  double y0 = 0.0;   // run-out level: top of the foundation
  double top = 0.0;  // level of the cover's surface
  HistoryCsv prep_csv, history, profiles;
  VtkSeries<2> vtk;
  RunCheckpoints checkpoints;
  DepositCache deposit_cache;   // the foundation's deposit, shared with other runs
  bool deposit_loaded = false;  // this run's foundation came from the cache
  std::shared_ptr<SurfacePressure<2>> surcharge;
  std::uint64_t layers_planned = 0;  // estimate of the stage's layers (progress only)
  std::vector<double> moved;         // scratch of soil_displacement()

  // The run's own state, saved in checkpoints (visit_state).
  Phase phase = Phase::kFoundation;
  std::uint64_t stage_step = 0;  // steps into the current settle()
  std::uint64_t layer = 0;       // layers deposited in the current stage
  std::uint8_t in_settle = 0;    // the current layer is settling
  std::uint64_t foundation = 0;  // grains of the foundation (the lowest ids)
  double node_mass_factor = 1.0;
  std::uint64_t total_steps = 0;
  nlohmann::json prep = nlohmann::json::object();
  Pull pull;

  Pullout(const PulloutSettings& settings, const RunOptions& options)
      : s(settings),
        opt(options),
        progress(options.quiet),
        rng(settings.seed),
        vtk(options.out_dir),
        checkpoints("pullout", 2, settings.resolved, options.out_dir, settings.checkpoint),
        deposit_cache(settings.deposit_cache, "pullout_foundation", settings.resolved,
                      {"anchor", "sheet", "surcharge", "pull", "analytic", "output", "refinement",
                       "checkpoint", "seeds", "title"}) {
    vtk.with_contacts(s.vtk_contacts);
    checkpoints.outputs({&prep_csv, &history, &profiles});
  }

  double elapsed() const { return checkpoints.elapsed(); }
  std::string prep_path() const { return opt.out_dir + "/preparation.csv"; }

  template <class Archive>
  void visit_state(Archive& a) {
    a(phase), a(stage_step), a(layer), a(in_settle), a(foundation), a(node_mass_factor);
    a(total_steps);
    archive_json(a, prep);
    std::string random = rng.state();
    a(random);
    if (Archive::kLoading && !rng.set_state(random))
      throw CheckpointError("unreadable random state");
    pull.visit(a);
  }

  // After a whole step: a checkpoint when due, and the stop on a signal.
  // Closes a step of a loop (io/step_loop.hpp): a checkpoint when due; a signal stops the
  // run by throwing Interrupted, so the loop never goes on from here.
  bool after_step() {
    checkpoints.after_step(total_steps, w.time, [&](StateWriter& runner, StateWriter& world) {
      visit_state(runner);
      runner(elapsed());
      for (const HistoryCsv* f : {&prep_csv, &history, &profiles})
        runner(static_cast<std::uint64_t>(f->rows()));
      vtk.save(runner);
      save_world_state(world, w);
    });
    return false;
  }

  void build() {
    Material sheet = s.soil;
    sheet.name = "sheet";
    sheet.friction = std::tan(s.interface_friction_deg * kDeg);
    sheet.rolling_friction = sheet.twisting_friction = 0.0;
    sheet.normal_cohesion = sheet.shear_cohesion = 0.0;
    w.materials = {s.soil, s.wall, sheet};
    auto plane = [&](const char* name, Vec point, Vec normal, double area) {
      Wall<2> wall;
      wall.name = name;
      wall.point = point;
      wall.normal = normal;
      wall.material = kWalls;
      wall.area = area;
      w.walls.push_back(wall);
    };
    plane("floor", Vec(0.0, 0.0), Vec(0.0, 1.0), s.box_length);
    plane("front", Vec(0.0, 0.0), Vec(1.0, 0.0), 0.0);
    plane("back", Vec(s.box_length, 0.0), Vec(-1.0, 0.0), 0.0);
    configure_deposit_world(w, s, s.interface_friction_deg, s.dt_safety, s.dt_update_interval,
                            opt.threads);
    kinds = resolve_kinds<2>(s.grains);
    areas = grain_areas(kinds, s.radius, s.radius_fuzz);
    y0 = s.foundation;
    top = y0 + s.anchor.cover;
  }

  void start() {
    prepare_output_dir(opt.out_dir);
    prep_csv.open(prep_path(), kPrepColumns);
    phase = Phase::kFoundation;
    if (auto c = deposit_cache.load()) {
      // The foundation as the cache holds it; the run goes on from the end of its deposit.
      DepositCache::restore(
          *c, w, [&](StateReader& a) { visit_state(a); }, prep_path(), &prep_csv, kPrepColumns);
      deposit_loaded = true;
      prep["deposit_cache"] = "loaded " + deposit_cache.path();
    }
  }

  // build(), then the newest valid checkpoint: the sheet and surcharge plate laid first.
  void resume() {
    const Checkpoint c = checkpoints.resume(s.file, {});
    StateReader in(c.runner.data(), c.runner.size());
    visit_state(in);
    std::uint64_t rows[3] = {0, 0, 0};
    double wall_before = 0.0;
    in(wall_before), in(rows[0]), in(rows[1]), in(rows[2]);
    vtk.restore(in);
    if (phase > Phase::kFoundation) lay_sheet();
    if (phase >= Phase::kConsolidation && s.surcharge > 0.0) add_surcharge_plate();
    StateReader win(c.world.data(), c.world.size());
    load_world_state(win, w);
    prep_csv.resume_rows(prep_path(), kPrepColumns, rows[0]);
    if (phase == Phase::kPull) {
      history.resume_rows(opt.out_dir + "/history.csv", kHistoryColumns, rows[1]);
      profiles.resume_rows(opt.out_dir + "/tension_profiles.csv", kProfileColumns, rows[2]);
    }
    checkpoints.resume_clock(wall_before);
  }

  void prep_row(double stage, double unb) {
    prep_csv.row({stage, static_cast<double>(w.step), w.time,
                  static_cast<double>(w.particles.size()), surface_level(w, 0.0, s.box_length), unb,
                  kinetic_energy(w)});
  }

  // Steps until the unbalanced force ratio falls below the settings' threshold. Resumes
  // where a checkpoint left it (stage_step).
  void settle(const std::string& stage, double stage_code) {
    const std::uint64_t every = 200;
    step_loop(
        w, total_steps, [] { return true; }, [&] { return ++stage_step % every == 0; },
        [&] {
          if (!w.measure_this_step) return false;
          const std::uint64_t k = stage_step;
          const double unb = unbalanced_force_ratio(w);
          progress.update(stage, w.step, w.time, -1.0,
                          std::to_string(w.particles.size()) + " grains, unbalanced " +
                              format_sig(unb) + " (at rest below " +
                              format_sig(s.settle_unbalanced) + ")");
          if (k % (5 * every) == 0) prep_row(stage_code, unb);
          if (k >= 5 * every && unb < s.settle_unbalanced && !soil_moving(w, s.soil.density))
            return true;
          if (k >= s.max_settle_steps)
            throw std::runtime_error(
                stage + ": the soil did not come to rest (unbalanced force " + format_number(unb) +
                " after " + std::to_string(k) +
                " steps); raise time.max_settle_steps or soil.settle_unbalanced");
          return false;
        },
        [&] { return after_step(); });
    stage_step = 0;
  }

  // Deposits layers over [x0, x1] until the surface there reaches `height`.
  void deposit_to(double height, double x0, double x1, const std::string& stage,
                  double stage_code) {
    for (;;) {
      if (!in_settle) {
        if (!(w.particles.size() == 0 || surface_level(w, x0, x1) < height)) break;
        const double base = w.particles.size() == 0 ? 0.0 : top_of_grains(w);
        const double from = w.particles.size() == 0 ? 0.0 : surface_level(w, x0, x1);
        const double dense = std::min(s.layer_thickness, height - from + 2.0 * s.radius);
        // Layers still to come, this one included (for the progress line; a layer settles
        // to less than its thickness, so it is an estimate).
        layers_planned = layer + static_cast<std::uint64_t>(
                                     std::max(1.0, std::ceil((height - from) / s.layer_thickness)));
        drop_layer(w, s, s.file, kinds, areas, rng, x0, x1, base, dense);
        ++layer;
        in_settle = 1;
      }
      settle(stage + " layer " + std::to_string(layer) +
                 (layers_planned >= layer ? " of about " + std::to_string(layers_planned) : ""),
             stage_code);
      in_settle = 0;
    }
    layer = 0;
  }

  // The sheet, its axis half a thickness above the foundation's top.
  void lay_sheet() {
    const auto corners = sheet_corners(s.anchor, y0 + 0.5 * s.thickness);
    const auto nodes = sheet_nodes(corners, s.element_length);
    std::vector<Vec> pts(nodes.begin(), nodes.end());
    w.spars.add_chain("sheet", pts, s.stiffness_J, s.mass_per_area, s.thickness, kSheet, s.bending);
    w.spars.flags[0] = kNodeDriven;  // the clamp, still until the pull
  }

  // Foundation: deposited, trimmed flat at the run-out level, the trench excavated; then
  // the sheet is laid and the foundation held (a face that stands while the trench is
  // open).
  void foundation_phase() {
    const auto& P = w.particles;
    if (!deposit_loaded) {
      deposit_to(y0 + 2.0 * s.radius, 0.0, s.box_length, "foundation", 1);
      if (deposit_cache.enabled()) {
        deposit_cache.store(
            w, [&](StateWriter& a) { visit_state(a); }, prep_path(), &prep_csv);
        prep["deposit_cache"] = "stored " + deposit_cache.path();
      }
    }
    const double t = s.thickness;
    remove_grains(w, grains_where(w, [&](std::size_t i) {
                    return P.pos[i].y() + P.radius[i] > y0 ||
                           overlaps_trench(s.anchor, y0, P.pos[i], P.radius[i] + t);
                  }));
    prep["foundation_grains"] = P.size();
    for (std::size_t i = 0; i < P.size(); ++i) w.particles.id[i] = static_cast<std::uint32_t>(i);
    lay_sheet();
    if (s.mass_scaling)
      node_mass_factor =
          scale_sheet_inertia(w, s.soil.young, s.stiffness_J, s.element_length, s.node_mass_factor);
    w.rebuild_needed = true;
    foundation = P.size();
    hold_grains(w, std::vector<char>(foundation, 1), true);
    phase = s.anchor.shape != "runout" ? Phase::kTrenchFill : Phase::kCover;
  }

  // The cover trimmed flat; the foundation released; the free face; the surcharge.
  void finish_fill() {
    const auto& P = w.particles;
    // Renumbering moved the held grains: find them by id (new grains have larger ids).
    auto is_foundation = [&](std::size_t i) { return P.id[i] < foundation; };
    remove_grains(w, grains_where(w, [&](std::size_t i) {
                    return !is_foundation(i) && P.pos[i].y() + P.radius[i] > top;
                  }));
    hold_grains(w, grains_where(w, is_foundation), false);
    prep["fill_grains"] = P.size() - foundation;
    if (s.anchor.front == "free") {
      // The front wall now holds the foundation only: the cover's face is free.
      Wall<2>& front = w.walls[kFrontWall];
      front.kind = WallKind::kSegment;
      front.point = Vec(0.0, -s.radius);
      front.end = Vec(0.0, y0);
      w.rebuild_needed = true;
    }
    if (s.surcharge > 0.0) add_surcharge_plate();
    set_soil_friction(w, s.soil, s.soil.friction);  // the soil's own friction from here on
    phase = Phase::kConsolidation;
  }

  void consolidation_phase() {
    settle("consolidation", 3);
    if (s.anchor.front == "free") {
      // Grains that fell off the free face are no longer part of the anchorage.
      const auto& P = w.particles;
      const std::size_t spilled =
          remove_grains(w, grains_where(w, [&](std::size_t i) { return P.pos[i].x() < 0.0; }));
      prep["spilled_grains"] = spilled;
      if (spilled > 0) {
        phase = Phase::kSpillSettle;
        return;
      }
    }
    after_consolidation();
  }

  void after_consolidation() {
    if (s.bonds) {
      prep["bonds"] = create_bonds(w, s.bond_gap_tolerance);
      phase = Phase::kBonded;
      return;
    }
    begin_pull();
  }

  // The plate on the cover, held at the surcharge pressure.
  void add_surcharge_plate() {
    Wall<2> plate;
    plate.name = "surcharge";
    plate.point = Vec(0.0, top + 0.5 * s.radius);
    plate.normal = Vec(0.0, -1.0);
    plate.material = kWalls;
    plate.area = s.box_length;
    w.walls.push_back(plate);
    w.resolve_pair_laws();
    set_interface_laws(w, std::tan(s.interface_friction_deg * kDeg));
    // Speed cap: a twentieth of a radius per step (a resumed run loads the saved cap).
    const double vmax = w.dt > 0.0 ? 0.05 * s.radius / w.dt : 0.0;
    surcharge = std::make_shared<SurfacePressure<2>>(w.walls.size() - 1, s.surcharge, vmax);
    w.controllers = {surcharge};
  }

  // End of the preparation: the anchoring zone, the analytic estimate, the initial
  // states, the output files of the pull; the clamp starts moving.
  void begin_pull() {
    auto& P = w.particles;
    auto& S = w.spars;
    prep["grains"] = P.size();
    prep["bodies"] = body_count(w);
    prep["steps"] = w.step;
    prep["time"] = w.time;
    Pull& u = pull;
    for (std::size_t i = 0; i < P.size(); ++i) P.id[i] = static_cast<std::uint32_t>(i);
    start_pull(u, w, s, y0, top, surcharge ? surcharge->pressure(w) : 0.0);
    write_pullout_states(opt.out_dir + "/states/grains_initial.csv",
                         opt.out_dir + "/states/sheet_initial.csv", w, u.column);
    if (s.vtk) vtk.write(w);
    history.open(opt.out_dir + "/history.csv", kHistoryColumns);
    profiles.open(opt.out_dir + "/tension_profiles.csv", kProfileColumns);
    w.local_damping = s.pull_damping;
    S.vel[0] = Vec(-s.rate, 0.0);
    phase = Phase::kPull;
  }

  // The free end pulled horizontally at a constant rate.
  void pull_phase() {
    auto& S = w.spars;
    Pull& u = pull;
    const double d_record = s.max_displacement / s.history_points;
    step_loop(
        w, total_steps, [&] { return u.displacement < s.max_displacement; },
        [&] {
          const double next_d = u.clamp0.x() - (S.pos[0].x() - s.rate * w.dt);
          return next_d >= u.next_record || next_d >= s.max_displacement;
        },
        [&] { return record_pull(d_record); }, [&] { return after_step(); });
    phase = Phase::kDone;
  }

  // After a step of the pull: the clamp's displacement and tension, a history row when
  // one is due, the tension profiles the displacement has reached. Never stops the loop
  // (false): the pull ends at its displacement.
  bool record_pull(double d_record) {
    auto& S = w.spars;
    Pull& u = pull;
    u.displacement = u.clamp0.x() - S.pos[0].x();
    u.add_step(w);
    // The last row is always written, even when a change of dt made the prediction miss it.
    if (w.measure_this_step || u.displacement >= s.max_displacement) {
      SheetPartLoads parts;
      const double T = u.end_row(parts);
      const double soil = anchoring_soil_displacement(u, w, false, moved),
                   median = anchoring_soil_displacement(u, w, true, moved);
      const double near = mean_grain_displacement(w, u.near, u.start);
      const double nodes = mean_embedded_node_displacement(w, u.node_start);
      history.row({static_cast<double>(w.step), w.time, u.displacement, T, S.tension[0], soil,
                   median, kinetic_energy(w), unbalanced_force_ratio(w),
                   static_cast<double>(w.stats.spar_contacts), near, nodes,
                   parts.carried[kRunoutPart], parts.normal[kRunoutPart], parts.carried[kBendPart],
                   parts.normal[kBendPart], parts.carried[kTrenchPart], parts.normal[kTrenchPart]});
      if (T > u.t_max) {
        u.t_max = T, u.d_at_max = u.displacement, u.soil_at_max = soil;
        u.soil_median_at_max = median, u.near_at_max = near, u.nodes_at_max = nodes;
        u.parts_at_max = parts;
      }
      while (u.next_record <= u.displacement) u.next_record += d_record;
      progress.update("pull", w.step, w.time, u.displacement / s.max_displacement,
                      "T " + format_sig(T) + " N/m");
    }
    while (!u.profile_at.empty() && u.displacement >= u.profile_at.back() - 1e-12) {
      double arc = 0.0;
      for (std::size_t e = 0; e < S.elements(); ++e) {
        const double len = S.length(e);
        profiles.row({u.profile_at.back(), arc + 0.5 * len, S.tension[e]});
        arc += len;
      }
      if (s.vtk) vtk.write(w);
      u.profile_at.pop_back();
    }
    return false;
  }

  void run_phases() {
    for (;;) {
      switch (phase) {
        case Phase::kFoundation:
          foundation_phase();
          break;
        case Phase::kTrenchFill:
          deposit_to(y0, s.anchor.runout_length, s.anchor.runout_length + s.anchor.trench_width,
                     "trench fill", 2);
          phase = Phase::kCover;
          break;
        case Phase::kCover:
          deposit_to(top + 2.0 * s.radius, 0.0, s.box_length, "cover", 2);
          finish_fill();
          break;
        case Phase::kConsolidation:
          consolidation_phase();
          break;
        case Phase::kSpillSettle:
          settle("consolidation", 3);
          after_consolidation();
          break;
        case Phase::kBonded:
          settle("bonded", 4);
          begin_pull();
          break;
        case Phase::kPull:
          pull_phase();
          break;
        case Phase::kDone:
          return;
      }
    }
  }
};

nlohmann::json run_pullout_test(const PulloutSettings& s, const RunOptions& opt) {
  Pullout run(s, opt);
  run_lab_phases(run, "pullout", s.resolved, opt);
  const World<2>& w = run.w;
  const Pull& u = run.pull;
  write_pullout_states(opt.out_dir + "/states/grains_final.csv",
                       opt.out_dir + "/states/sheet_final.csv", w, u.column);
  if (s.vtk) run.vtk.write(w);

  nlohmann::json results;
  results["preparation"] = run.prep;
  pull_results(u, w, s, results);
  results["sheet"]["node_mass_factor"] = run.node_mass_factor;
  return write_run_summary(opt.out_dir, "pullout", "completed", s.resolved, results,
                           timing_json(w, run.elapsed(), run.total_steps, opt.threads));
}
}  // namespace

nlohmann::json run_pullout(const PulloutSettings& s, const RunOptions& opt) {
  return summarise_interruption("pullout", s.resolved, opt,
                                [&] { return run_pullout_test(s, opt); });
}

}  // namespace geodem
