#include "scene/run_scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "base/error.hpp"
#include "contacts/bonds.hpp"
#include "io/interrupt.hpp"
#include "io/output_files.hpp"
#include "io/particle_table.hpp"
#include "io/progress.hpp"
#include "io/run_checkpoints.hpp"
#include "io/step_loop.hpp"
#include "measure/contact_network.hpp"
#include "measure/displacement.hpp"
#include "measure/measurements.hpp"
#include "scene/build_scene.hpp"
#include "scene/scene_domain.hpp"
#include "scene/scene_stages.hpp"
#include "scene/scene_start.hpp"
#include "study/study_comm.hpp"
#include "world/step.hpp"
#include "world/world_state.hpp"

namespace geodem {

namespace {

const char* axis(int k) {
  return k == 0 ? "x" : (k == 1 ? "y" : "z");
}

// The box around the grains (with their radii, or their centres); in a decomposed world
// every rank's.
template <int D>
Box<D> grains_box(const World<D>& w, bool radii = true) {
  using Vec = typename Dim<D>::Vec;
  const double inf = std::numeric_limits<double>::infinity();
  Box<D> b{Vec::Constant(inf), Vec::Constant(-inf)};
  for (std::size_t i = 0; i < w.particles.size(); ++i) {
    const Vec r = Vec::Constant(radii ? w.particles.radius[i] : 0.0);
    b.lo = b.lo.cwiseMin(w.particles.pos[i] - r);
    b.hi = b.hi.cwiseMax(w.particles.pos[i] + r);
  }
  if (w.domain)
    for (int k = 0; k < D; ++k)
      b.lo[k] = w.domain->min_over_ranks(b.lo[k]), b.hi[k] = -w.domain->min_over_ranks(-b.hi[k]);
  if (!(b.lo[0] <= b.hi[0])) return Box<D>{Vec::Zero(), Vec::Ones()};  // a chain alone
  return b;
}

template <int D>
nlohmann::json run(const SceneSettings& s, const RunOptions& opt) {
  // Rank 0 of a decomposed run writes the outputs and checkpoints; the others read.
  const bool root = !opt.decompose || comm::rank() == 0;
  World<D> w;
  build_world<D>(s, w);
  // (also on resume: the rebuilt world must have the walls and chains the run had)
  if (!s.start_checkpoint.empty()) start_from_checkpoint(s, w);
  w.threads = opt.threads;
  prepare_output_dir(opt.out_dir);

  // The runner's own state in a checkpoint, beside the world's.
  std::uint64_t bonds_created = 0;
  std::uint8_t finished = 0;  // the final outputs are written
  bool at_rest = false;
  std::string stop_reason = "end of duration";
  // Stages: the current one, whether its start edits are made, where it started, and the
  // reports of those finished (JSON text). A scene without [[stages]] is one stage.
  const bool staged = !s.stages.empty();
  const std::uint64_t stage_count = staged ? s.stages.size() : 1;
  std::uint64_t stage = 0;
  std::uint8_t stage_started = staged ? 0 : 1;
  double stage_t0 = 0.0;
  std::uint64_t stage_s0 = 0;
  std::string stage_log = "[]";
  // Positions by grain id at the start of the run or of the stage (the VTK displacements).
  std::vector<typename Dim<D>::Vec> reference;
  DomainCheckpoint<D> saved_domain;  // a decomposed run's keys and contact history
  std::uint8_t was_decomposed = 0;   // the checkpoint resumed is a decomposed run's
  RunCheckpoints checkpoints("scene", D, s.resolved, opt.out_dir, s.checkpoint);
  Checkpoint resumed;
  StateReader runner_in(nullptr, 0);
  if (opt.resume) {
    // A finished run may be extended, and may stop on other criteria.
    resumed = checkpoints.resume(s.file, {"time.duration", "time.steps", "stop"}, root);
    runner_in = StateReader(resumed.runner.data(), resumed.runner.size());
    runner_in(stage), runner_in(stage_started), runner_in(stage_t0), runner_in(stage_s0);
    runner_in(stage_log), runner_in(reference), runner_in(was_decomposed);
    if (was_decomposed) saved_domain.visit(runner_in);
    // The saved world has the walls and servos of the stages begun: redo those first.
    for (std::uint64_t k = 0; staged && k < std::min(stage + stage_started, stage_count); ++k)
      start_stage(s, k, w, true);
    StateReader in(resumed.world.data(), resumed.world.size());
    load_world_state(in, w);
  } else if (s.bonds_initial) {
    bonds_created = create_bonds(w, s.bond_gap_tolerance);
  }
  // Over the ranks of mpirun: each keeps its slab of the world it built (bonds included) or
  // loaded from a checkpoint (on any number of ranks). One process that resumes a decomposed
  // run goes on as a domain of one rank (the same bits).
  const auto domain = opt.decompose || was_decomposed
                          ? decompose_scene(s, w, was_decomposed ? &saved_domain : nullptr,
                                            !opt.decompose, opt.rebalance_every)
                          : nullptr;
  saved_domain = DomainCheckpoint<D>{};
  auto positions = [&] { return domain ? domain_positions_by_id(w, *domain) : positions_by_id(w); };

  std::optional<Box<D>> box;
  if (s.output.measure_box) {
    Box<D> b;
    for (int k = 0; k < D; ++k)
      b.lo[k] = s.output.measure_box->first[k], b.hi[k] = s.output.measure_box->second[k];
    box = b;
  }

  std::vector<std::string> cols = {"step",         "time",           "wall_s",
                                   "dt",           "kinetic_energy", "unbalanced",
                                   "coordination", "contacts",       "wall_contacts"};
  if (staged) cols.insert(cols.begin() + 2, "stage");
  if (s.bonds_initial) cols.insert(cols.end(), {"bonds", "broken_bonds"});
  if (box) cols.push_back("porosity");
  for (int a = 0; a < D; ++a)
    for (int b = a; b < D; ++b) cols.push_back(std::string("stress_") + axis(a) + axis(b));
  for (int a = 0; a < D; ++a)
    for (int b = a; b < D; ++b) cols.push_back(std::string("fabric_") + axis(a) + axis(b));
  cols.push_back("fabric_anisotropy");
  // Every wall the scene ever has, in order of appearance; NaN while one is absent.
  std::vector<Wall<D>> wall_cols;
  for (const auto& spec : s.walls)
    for (const auto& wall : walls_of<D>(spec, s.materials)) wall_cols.push_back(wall);
  for (const auto& st : s.stages)
    for (const auto& spec : st.add_walls)
      for (const auto& wall : walls_of<D>(spec, s.materials)) wall_cols.push_back(wall);
  for (const auto& wall : wall_cols) {
    for (int k = 0; k < D; ++k) cols.push_back("wall_" + wall.name + "_f" + axis(k));
    if (wall.area > 0.0) cols.push_back("wall_" + wall.name + "_stress");
  }
  auto find_wall = [&w](const std::string& name) -> const Wall<D>* {
    for (const auto& wall : w.walls)
      if (wall.name == name) return &wall;
    return nullptr;
  };
  for (const auto& c : w.spars.chains)
    for (const char* q : {"_tension_first", "_tension_last", "_tension_max"})
      cols.push_back("chain_" + c.name + q);
  // Tensions of a chain's first and last elements, and its largest.
  auto chain_tensions = [&w](const typename SparChains<D>::Chain& c) {
    const auto& S = w.spars;
    const std::size_t e0 = c.first_element, e1 = c.first_element + c.node_count - 2;
    double tmax = 0.0;
    for (std::size_t e = e0; e <= e1; ++e) tmax = std::max(tmax, S.tension[e]);
    return std::array<double, 3>{S.tension[e0], S.tension[e1], tmax};
  };
  HistoryCsv history;
  checkpoints.outputs({&history});
  VtkSeries<D> vtk(opt.out_dir);
  vtk.with_contacts(s.output.vtk_contacts);
  // (positions by id for the frames alone: a decomposed run gathers them from every rank)
  const bool displacements = s.output.vtk && s.output.displacement_from != "none";
  if (displacements) vtk.with_reference(&reference);
  if (opt.resume) {
    auto& in = runner_in;
    double wall_before = 0.0;  // wall time of the run before the checkpoint
    in(bonds_created), in(wall_before), in(finished), in(stop_reason);
    checkpoints.resume_clock(wall_before);
    vtk.restore(in, root);
    // A finished run goes on if its duration or step count was raised, unless it stopped
    // at rest.
    at_rest = finished && stop_reason != "end of duration";
    if (root) history.resume(opt.out_dir + "/history.csv", cols, static_cast<double>(w.step));
  } else if (root) {
    history.open(opt.out_dir + "/history.csv", cols);
  }

  auto elapsed = [&checkpoints] { return checkpoints.elapsed(); };
  auto checkpoint = [&] {
    // A decomposed run: rank 0 saves the whole domain as one world (grains in key order, no
    // list: the history goes as records with the keys, SlabDomain::checkpoint).
    DomainWorldOnRank0<D> whole(w, domain.get(), saved_domain);
    if (!root) return;
    checkpoints.write_with(w.step, w.time, [&](StateWriter& runner, StateWriter& world) {
      runner(stage), runner(stage_started), runner(stage_t0), runner(stage_s0), runner(stage_log);
      const std::uint8_t decomposed = domain ? 1 : 0;
      runner(reference), runner(decomposed);
      if (domain) saved_domain.visit(runner);
      runner(bonds_created), runner(elapsed()), runner(finished), runner(stop_reason);
      vtk.save(runner);
      save_world_state(world, w);
    });
  };
  auto record = [&]() {
    const double wall_now = elapsed();
    std::vector<double> row = {static_cast<double>(w.step),
                               w.time,
                               wall_now,
                               w.dt,
                               kinetic_energy(w),
                               unbalanced_force_ratio(w),
                               coordination_number(w),
                               static_cast<double>(w.stats.contacts),
                               static_cast<double>(w.stats.wall_contacts)};
    if (staged) row.insert(row.begin() + 2, static_cast<double>(stage + 1));
    if (s.bonds_initial) {
      row.push_back(static_cast<double>(intact_bonds(w)));
      row.push_back(static_cast<double>(broken_bond_count(w)));
    }
    const Box<D> vb = box ? *box : grains_box(w);
    if (box) row.push_back(porosity_in_box(w, *box));
    const auto sigma = average_stress(w, vb.volume());
    for (int a = 0; a < D; ++a)
      for (int b = a; b < D; ++b) row.push_back(sigma(a, b));
    const auto fabric = fabric_tensor(w);
    for (int a = 0; a < D; ++a)
      for (int b = a; b < D; ++b) row.push_back(fabric(a, b));
    row.push_back(fabric_anisotropy<D>(fabric));
    const double absent = std::numeric_limits<double>::quiet_NaN();
    for (const auto& col : wall_cols) {
      const Wall<D>* wall = find_wall(col.name);
      for (int k = 0; k < D; ++k) row.push_back(wall ? wall->force[k] : absent);
      if (col.area > 0.0) row.push_back(wall ? wall->normal_stress() : absent);
    }
    for (const auto& c : w.spars.chains)
      for (double t : chain_tensions(c)) row.push_back(t);
    if (root) history.row(row);
  };

  // What a finished stage reports: how it ended, the stress on each wall with an area, and
  // each servo's target beside the stress it holds.
  auto stage_report = [&](const StageSpec& st, const std::string& reason) {
    nlohmann::json r = {{"name", st.name},
                        {"stop_reason", reason},
                        {"steps", w.step - stage_s0},
                        {"start_time", stage_t0},
                        {"end_time", w.time}};
    nlohmann::json walls = nlohmann::json::object();
    for (const auto& wall : w.walls)
      if (wall.area > 0.0)
        walls[wall.name] = {
            {"normal_stress", wall.normal_stress()},
            {"point", std::vector<double>(wall.point.data(), wall.point.data() + D)}};
    r["walls"] = walls;
    nlohmann::json servos = nlohmann::json::array();
    for (const auto& m : st.walls)
      if (m.servo)
        for (auto i : wall_indices(w, m.wall)) {
          const double sigma = w.walls[i].normal_stress();
          servos.push_back({{"wall", w.walls[i].name},
                            {"target", m.stress},
                            {"stress", sigma},
                            {"relative_error", m.stress > 0.0 ? sigma / m.stress - 1.0 : sigma}});
        }
    if (!servos.empty()) r["servos"] = servos;
    return r;
  };

  Progress progress(opt.quiet || !root);
  std::string status = "completed";
  std::string message;
  if (!opt.resume) {
    if (displacements) reference = positions();
    update_timestep(w);
    if (s.output.vtk) vtk.write(w);
  }
  const double infinite = std::numeric_limits<double>::infinity();
  const double duration = s.time.duration > 0.0 ? s.time.duration : infinite;
  const std::uint64_t max_steps =
      s.time.steps > 0 ? s.time.steps : std::numeric_limits<std::uint64_t>::max();
  // A finished scene without stages goes on if its duration or step count was raised,
  // unless it stopped at rest.
  if (opt.resume && !staged && finished && !at_rest) stage = 0, stage_started = 1;
  // (a resumed run has the forces of its last step: the same figure as before it stopped)
  double unbalanced =
      opt.resume ? unbalanced_force_ratio(w) : std::numeric_limits<double>::quiet_NaN();
  const std::uint64_t first_step = w.step;
  try {
    while (!at_rest && stage < stage_count) {
      if (!stage_started) {
        start_stage(s, stage, w, false);
        if (s.output.displacement_from == "stage") reference = positions();
        update_timestep(w);
        stage_started = 1, stage_t0 = w.time, stage_s0 = w.step;
      }
      const StageSpec* st = staged ? &s.stages[stage] : nullptr;
      const StopSpec& stop = st ? st->stop : s.stop;
      const std::string label = st ? st->name : "scene";
      const double end_time = !st                  ? duration
                              : st->duration > 0.0 ? stage_t0 + st->duration
                                                   : infinite;
      const std::uint64_t end_step = !st             ? max_steps
                                     : st->steps > 0 ? stage_s0 + st->steps
                                                     : std::numeric_limits<std::uint64_t>::max();
      std::string reason = "end of duration";
      std::uint64_t stepped = 0;
      auto stop_met = [&] {
        if (w.measure_this_step) {
          record();
          unbalanced = unbalanced_force_ratio(w);
          const double fraction = std::max(
              (w.time - stage_t0) / (end_time - stage_t0),
              static_cast<double>(w.step - stage_s0) / static_cast<double>(end_step - stage_s0));
          progress.update(label, w.step, w.time, std::min(fraction, 1.0),
                          "unbalanced " + format_sig(unbalanced), std::min(fraction, 1.0));
          if (w.time - stage_t0 >= stop.min_time &&
              (stop.unbalanced_below > 0.0 || stop.kinetic_below > 0.0)) {
            const bool ub_ok = stop.unbalanced_below <= 0.0 || unbalanced < stop.unbalanced_below;
            const bool ke_ok = stop.kinetic_below <= 0.0 || kinetic_energy(w) < stop.kinetic_below;
            bool servos_ok = true;  // each servo holds its target
            for (const auto& m : st ? st->walls : std::vector<WallMotionSpec>{})
              if (m.servo)
                for (auto i : wall_indices(w, m.wall))
                  servos_ok &= std::abs(w.walls[i].normal_stress() - m.stress) <=
                               stop.servo_tolerance * m.stress;
            if (ub_ok && ke_ok && servos_ok) {
              reason = "at rest (stop criteria met)";
              return true;
            }
          }
        }
        return false;
      };
      step_loop(
          w, stepped, [&] { return w.step < end_step && w.time < end_time * (1.0 - 1e-12); },
          [&] {
            const bool last = w.step + 1 >= end_step || w.time + w.dt >= end_time * (1.0 - 1e-12);
            return last || w.step % s.output.history_every == 0;
          },
          stop_met,
          [&] {
            if (s.output.vtk && s.output.vtk_every > 0 && w.step % s.output.vtk_every == 0)
              vtk.write(w);
            // A checkpoint closes a step whose outputs are all written.
            // (the ranks of a decomposed world stop together, at a step they agree on)
            if (domain ? w.step % 64 == 0 && domain->any_rank(interrupt_signal() != 0)
                       : interrupt_signal() != 0) {
              checkpoint();
              status = "interrupted";
              return true;
            }
            const bool due = checkpoints.due(w.step);  // (wall-clock checkpoints: any rank's)
            if (domain && s.checkpoint.enabled() ? domain->any_rank(due) : due) checkpoint();
            return false;
          });
      if (status != "completed") break;
      stop_reason = reason;
      if (st) {
        nlohmann::json log = nlohmann::json::parse(stage_log);
        log.push_back(stage_report(*st, reason));
        stage_log = log.dump();
      }
      ++stage, stage_started = 0;
    }
    if (status == "completed") check_finite(w);
  } catch (const InstabilityError& e) {
    status = "unstable";
    message = checkpoints.diagnosis(std::string(e.what()) +
                                    " [the scenario's keys: time.step (seconds or \"auto\"), "
                                    "time.safety, materials' young or kn]");
  }
  progress.finish();
  const double wall_s = elapsed();
  if (status == "completed" && !(finished && w.step == first_step)) {
    if (s.output.vtk && (s.output.vtk_every == 0 || w.step % s.output.vtk_every != 0)) vtk.write(w);
    // The final packing, readable by [[particle_files]] (or [start] of another scene).
    if (domain) {  // the grains of every rank, in id order
      World<D> all;
      all.time = w.time, all.step = w.step;
      all.particles = grains_on_rank0(w, *domain);
      if (root) write_particle_table(opt.out_dir + "/particles.csv", all, s.materials);
    } else {
      write_particle_table(opt.out_dir + "/particles.csv", w, s.materials);
    }
    finished = 1;
    if (s.checkpoint.enabled()) checkpoint();
  }

  nlohmann::json results;
  results["status"] = status;
  results["stop_reason"] = status == "completed" ? stop_reason
                           : status == "interrupted"
                               ? "signal " + std::to_string(interrupt_signal())
                               : message;
  if (!checkpoints.last().empty()) results["checkpoint"] = checkpoints.last();
  results["time"] = w.time;
  results["steps"] = w.step;
  results["dt"] = w.dt;
  const auto [grains, clumps] = grain_and_clump_counts(w);
  results["particles"] = grains;
  results["clumps"] = clumps;
  if (s.bonds_initial) {
    results["bonds_created"] = bonds_created;
    results["bonds_broken"] = broken_bond_count(w);
  }
  if (status == "completed") {
    results["kinetic_energy"] = kinetic_energy(w);
    results["unbalanced"] =
        std::isfinite(unbalanced) ? nlohmann::json(unbalanced) : nlohmann::json();
    results["coordination"] = coordination_number(w);
    if (box) results["porosity"] = porosity_in_box(w, *box);
    const auto fabric = fabric_tensor(w);
    nlohmann::json rows = nlohmann::json::array();
    for (int a = 0; a < D; ++a) {
      std::vector<double> row(D);
      for (int b = 0; b < D; ++b) row[b] = fabric(a, b);
      rows.push_back(row);
    }
    results["fabric"] = {{"tensor", rows}, {"anisotropy", fabric_anisotropy<D>(fabric)}};
  }
  if (staged) results["stages"] = nlohmann::json::parse(stage_log);
  results["total_weight"] = body_weight(w);
  if (body_count(w) > 0) {  // extent of the grain centres
    const Box<D> c = grains_box(w, false);
    results["centres_min"] = std::vector<double>(c.lo.data(), c.lo.data() + D);
    results["centres_max"] = std::vector<double>(c.hi.data(), c.hi.data() + D);
  }
  nlohmann::json walls = nlohmann::json::object();
  for (const auto& wall : w.walls) {
    nlohmann::json f = nlohmann::json::array();
    for (int k = 0; k < D; ++k) f.push_back(wall.force[k]);
    walls[wall.name] = {{"force", f}};
    if (wall.kind == WallKind::kPlane)
      walls[wall.name]["normal_force"] = -wall.force.dot(wall.normal);
    if (wall.area > 0.0) walls[wall.name]["normal_stress"] = wall.normal_stress();
  }
  results["walls"] = walls;
  if (!w.spars.empty()) {
    nlohmann::json chains = nlohmann::json::object();
    for (const auto& c : w.spars.chains) {
      const auto t = chain_tensions(c);
      chains[c.name] = {{"nodes", c.node_count},
                        {"elements", c.node_count - 1},
                        {"tension_first", t[0]},
                        {"tension_last", t[1]},
                        {"tension_max", t[2]}};
    }
    results["chains"] = chains;
  }

  nlohmann::json timing = timing_json(w, wall_s, w.step, opt.threads);
  if (domain) {  // the whole domain's grains and rate, rank 0's times
    const std::size_t all = grains;
    timing["ranks"] = domain->ranks();
    timing["particles"] = all;
    timing["particle_steps_per_s"] =
        wall_s > 0.0 ? static_cast<double>(w.step) * static_cast<double>(all) / wall_s : 0.0;
  }
  const nlohmann::json summary =
      root ? write_run_summary(opt.out_dir, "scene", status, s.resolved, results, timing)
           : nlohmann::json{{"results", results}};
  if (status == "unstable") throw InstabilityError(message);
  if (status == "interrupted") throw Interrupted{interrupt_signal(), checkpoints.last()};
  return summary;
}

}  // namespace

nlohmann::json run_scene(const SceneSettings& settings, const RunOptions& options) {
  return settings.dimension == 2 ? run<2>(settings, options) : run<3>(settings, options);
}

}  // namespace geodem
