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
#include "lab/pullout_runner.hpp"

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
#include "lab/lab_domain.hpp"
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

}  // namespace

void PulloutRun::save(StateWriter& runner, StateWriter& world) {
  visit_state(runner);
  runner(elapsed());
  for (const HistoryCsv* f : {&prep_csv, &history, &profiles})
    runner(static_cast<std::uint64_t>(f->rows()));
  vtk.save(runner);
  domain.visit(runner, false);
  save_world_state(world, w);
}

bool PulloutRun::after_step() {
  auto write = [&](StateWriter& runner, StateWriter& world) { save(runner, world); };
  if (!domain)
    checkpoints.after_step(total_steps, w.time, write);
  else
    domain.after_step(w, nullptr, checkpoints, total_steps, [&] {
      if (root) checkpoints.write_with(total_steps, w.time, write);
    });
  return false;
}

void PulloutRun::build() {
  w.materials = deposit_materials(s.soil, s.wall, s.interface_friction_deg);
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

void PulloutRun::start() {
  prepare_output_dir(opt.out_dir);
  if (root) prep_csv.open(prep_path(), kPrepColumns);
  phase = Phase::kFoundation;
  if (auto c = LabDomain<2>::load_deposit(deposit_cache, opt)) {
    // The foundation as the cache holds it; the run goes on from the end of its deposit.
    DepositCache::restore(
        *c, w,
        [&](StateReader& a) {
          visit_state(a);
          domain.load_deposit_domain(a, opt);
        },
        prep_path(), root ? &prep_csv : nullptr, kPrepColumns);
    domain.spread_deposit(w, s.file, opt);
    deposit_loaded = true;
    prep["deposit_cache"] = "loaded " + deposit_cache.path();
  }
}

void PulloutRun::resume() {
  const Checkpoint c = checkpoints.resume(s.file, {}, root);
  StateReader in(c.runner.data(), c.runner.size());
  visit_state(in);
  std::uint64_t rows[3] = {0, 0, 0};
  double wall_before = 0.0;
  in(wall_before), in(rows[0]), in(rows[1]), in(rows[2]);
  vtk.restore(in, root);
  domain.visit(in, false);
  if (phase > Phase::kFoundation) lay_sheet();
  if (phase >= Phase::kConsolidation && s.surcharge > 0.0) add_surcharge_plate();
  StateReader win(c.world.data(), c.world.size());
  load_world_state(win, w);
  if (root) {
    prep_csv.resume_rows(prep_path(), kPrepColumns, rows[0]);
    if (phase == Phase::kPull) {
      history.resume_rows(opt.out_dir + "/history.csv", kHistoryColumns, rows[1]);
      profiles.resume_rows(opt.out_dir + "/tension_profiles.csv", kProfileColumns, rows[2]);
    }
  }
  checkpoints.resume_clock(wall_before);
  domain.decompose(w, nullptr, s.file, opt, domain.decomposed);
}

void PulloutRun::prep_row(double stage, double unb) {
  const std::vector<double> row = {stage,
                                   static_cast<double>(w.step),
                                   w.time,
                                   static_cast<double>(grain_count()),
                                   surface_level(w, 0.0, s.box_length),
                                   unb,
                                   kinetic_energy(w)};
  if (root) prep_csv.row(row);
}

void PulloutRun::settle(const std::string& stage, double stage_code) {
  const std::uint64_t every = 200;
  step_loop(
      w, total_steps, [] { return true; }, [&] { return ++stage_step % every == 0; },
      [&] {
        if (!w.measure_this_step) return false;
        const std::uint64_t k = stage_step;
        const double unb = unbalanced_force_ratio(w);
        progress.update(stage, w.step, w.time, -1.0,
                        std::to_string(grain_count()) + " grains, unbalanced " + format_sig(unb) +
                            " (at rest below " + format_sig(s.settle_unbalanced) + ")");
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

void PulloutRun::deposit_to(double height, double x0, double x1, const std::string& stage,
                            double stage_code) {
  for (;;) {
    if (!in_settle) {
      const bool empty = grain_count() == 0;
      if (!(empty || surface_level(w, x0, x1) < height)) break;
      const double base = empty ? 0.0 : top_of_solids(w);
      const double from = empty ? 0.0 : surface_level(w, x0, x1);
      const double dense = std::min(s.layer_thickness, height - from + 2.0 * s.radius);
      // Layers still to come, this one included (for the progress line; a layer settles
      // to less than its thickness, so it is an estimate).
      layers_planned = layer + static_cast<std::uint64_t>(
                                   std::max(1.0, std::ceil((height - from) / s.layer_thickness)));
      // (a decomposed run: every rank drops the same layer and keeps its own grains of it)
      const std::size_t before = w.particles.size(), clumps_before = w.clumps.size();
      drop_layer(w, s, s.file, kinds, areas, rng, x0, x1, base, dense);
      domain.grains_added(w, before, clumps_before, s.file, opt);
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

void PulloutRun::lay_sheet() {
  const auto nodes = sheet_path_nodes(s.anchor, y0 + 0.5 * s.thickness, s.element_length);
  std::vector<Vec> pts(nodes.begin(), nodes.end());
  // (its rest turns are the laid shape until the fill holds it: finish_fill)
  w.spars.add_chain("sheet", pts, s.stiffness_J, s.mass_per_area, s.thickness, kSheet, s.bending);
  w.spars.flags[0] = kNodeDriven;  // the clamp, still until the pull
}

void PulloutRun::foundation_phase() {
  const auto& P = w.particles;
  if (!deposit_loaded) {
    deposit_to(y0 + 2.0 * s.radius, 0.0, s.box_length, "foundation", 1);
    if (deposit_cache.enabled()) {
      // (a decomposed run: rank 0 stores the whole foundation, with its domain's keys)
      domain.store_deposit(w, root, opt, [&](auto&& visit_domain) {
        deposit_cache.store(
            w,
            [&](StateWriter& a) {
              visit_state(a);
              visit_domain(a);
            },
            prep_path(), &prep_csv);
      });
      prep["deposit_cache"] = "stored " + deposit_cache.path();
    }
  }
  const double t = s.thickness;
  remove_grains(w, grains_where(w, [&](std::size_t i) {
                  return P.pos[i].y() + P.radius[i] > y0 ||
                         overlaps_trench(s.anchor, y0, P.pos[i], P.radius[i] + t);
                }));
  prep["foundation_grains"] = grain_count();
  // The foundation's grains are those of ids below `foundation`: one process numbers them
  // from 0; a decomposed run keeps its ids (new grains take ids from next_id on).
  if (!domain)
    for (std::size_t i = 0; i < P.size(); ++i) w.particles.id[i] = static_cast<std::uint32_t>(i);
  foundation = domain ? P.next_id : P.size();
  lay_sheet();
  if (s.mass_scaling)
    node_mass_factor =
        scale_sheet_inertia(w, s.soil.young, s.stiffness_J, s.element_length, s.node_mass_factor);
  w.rebuild_needed = true;
  hold_grains(w, std::vector<char>(P.size(), 1), true);
  phase = s.anchor.shape != "runout" ? Phase::kTrenchFill : Phase::kCover;
}

void PulloutRun::finish_fill() {
  const auto& P = w.particles;
  // Renumbering moved the held grains: find them by id (new grains have larger ids).
  auto is_foundation = [&](std::size_t i) { return P.id[i] < foundation; };
  remove_grains(w, grains_where(w, [&](std::size_t i) {
                  return !is_foundation(i) && P.pos[i].y() + P.radius[i] > top;
                }));
  hold_grains(w, grains_where(w, is_foundation), false);
  prep["fill_grains"] = count_grains([&](std::size_t i) { return !is_foundation(i); });
  // A sheet flat at rest, as off the roll: the soil now holds it in its laid shape, and
  // no turn travels with the material as it is pulled round the bend.
  if (s.rest_flat) std::fill(w.spars.rest_turn.begin(), w.spars.rest_turn.end(), 0.0);
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

void PulloutRun::consolidation_phase() {
  settle("consolidation", 3);
  if (s.anchor.front == "free") {
    // Grains that fell off the free face are no longer part of the anchorage.
    const auto& P = w.particles;
    const std::size_t before = grain_count();
    remove_grains(w, grains_where(w, [&](std::size_t i) { return P.pos[i].x() < 0.0; }));
    const std::size_t spilled = before - grain_count();
    prep["spilled_grains"] = spilled;
    if (spilled > 0) {
      phase = Phase::kSpillSettle;
      return;
    }
  }
  after_consolidation();
}

void PulloutRun::after_consolidation() {
  if (s.bonds) {
    prep["bonds"] = create_bonds(w, s.bond_gap_tolerance);
    phase = Phase::kBonded;
    return;
  }
  begin_pull();
}

void PulloutRun::add_surcharge_plate() {
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

void PulloutRun::run_phases() {
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

namespace {

nlohmann::json run_pullout_test(const PulloutSettings& s, const RunOptions& opt) {
  PulloutRun run(s, opt);
  naming_decomposition_errors(s.file, [&] { run_lab_phases(run, "pullout", s.resolved, opt); });
  const World<2>& w = run.w;
  const Pull& u = run.pull;
  const Particles<2>& grains = run.all_grains();
  if (run.root)
    write_pullout_states(opt.out_dir + "/states/grains_final.csv",
                         opt.out_dir + "/states/sheet_final.csv", grains, w.spars, u.column);
  if (s.vtk) run.vtk.write(w);

  nlohmann::json results;
  results["preparation"] = run.prep;
  pull_results(u, w, grains, s, results);
  results["sheet"]["node_mass_factor"] = run.node_mass_factor;
  nlohmann::json timing = timing_json(w, run.elapsed(), run.total_steps, opt.threads);
  if (run.domain) run.domain.add_timing(timing, w, run.total_steps);
  if (!opt.primary) return {{"results", results}};
  return write_run_summary(opt.out_dir, "pullout", "completed", s.resolved, results, timing);
}
}  // namespace

nlohmann::json run_pullout(const PulloutSettings& s, const RunOptions& opt) {
  return summarise_interruption("pullout", s.resolved, opt,
                                [&] { return run_pullout_test(s, opt); });
}

}  // namespace geodem
