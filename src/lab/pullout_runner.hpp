// The runner of the pull-out test (docs/lab_tests.md, "Pull-out"), a phase machine
// (lab/lab_phases.hpp): its preparation in lab/run_pullout.cpp, the pull in
// lab/pullout_pull.cpp. In a decomposed run (docs/parallel.md) every rank runs it on its part
// of the world, spread once the first layer is dropped; rank 0 writes the outputs.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "base/random.hpp"
#include "controllers/surface_pressure.hpp"
#include "io/checkpoint.hpp"
#include "io/output_files.hpp"
#include "io/progress.hpp"
#include "io/run_checkpoints.hpp"
#include "io/run_output.hpp"
#include "lab/deposit_cache.hpp"
#include "lab/lab_domain.hpp"
#include "lab/pullout_results.hpp"
#include "lab/pullout_settings.hpp"
#include "lab/soil_deposit.hpp"
#include "scene/scene_domain.hpp"
#include "world/world.hpp"

namespace geodem {

struct PulloutRun {
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

  const PulloutSettings& s;
  const RunOptions& opt;
  const bool root;  // writes the outputs: one process, or rank 0 of a decomposed run
  World<2> w;
  // Over the ranks of mpirun (docs/parallel.md): spread once the first layer is dropped.
  LabDomain<2> domain;
  Particles<2> gathered;  // a decomposed run's grains, gathered for the measures by id
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
  std::uint64_t layers_planned = 0;       // estimate of the stage's layers (progress only)
  std::vector<double> moved, near_moved;  // scratch of the history row's measures

  // The run's own state, saved in checkpoints (visit_state).
  Phase phase = Phase::kFoundation;
  std::uint64_t stage_step = 0;  // steps into the current settle()
  std::uint64_t layer = 0;       // layers deposited in the current stage
  std::uint8_t in_settle = 0;    // the current layer is settling
  std::uint64_t foundation = 0;  // the foundation's grains are those of ids below this
  double node_mass_factor = 1.0;
  std::uint64_t total_steps = 0;
  nlohmann::json prep = nlohmann::json::object();
  Pull pull;

  PulloutRun(const PulloutSettings& settings, const RunOptions& options)
      : s(settings),
        opt(options),
        root(options.primary),
        progress(options.quiet || !options.primary),
        rng(settings.seed),
        vtk(options.out_dir),
        checkpoints("pullout", 2, settings.resolved, options.out_dir, settings.checkpoint),
        deposit_cache(settings.deposit_cache,
                      LabDomain<2>::deposit_stage("pullout_foundation", options), settings.resolved,
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

  // The runner's part of a checkpoint and the world's (rank 0's whole domain when
  // decomposed: DomainWorldOnRank0).
  void save(StateWriter& runner, StateWriter& world);

  // Closes a step of a loop (io/step_loop.hpp): a checkpoint when due; a signal stops the
  // run by throwing Interrupted, so the loop never goes on from here.
  bool after_step();

  // The whole sample's grains: the world's in one process; in a decomposed run every rank's
  // own, gathered in id order on every rank (all ranks call it).
  const Particles<2>& all_grains() {
    if (!domain) return w.particles;
    gathered = domain_grains(w);
    return gathered;
  }
  // A decomposed run's measures of a history row: the anchoring zone's displacements toward
  // the pull (`zone`) and the lengths of the displacements of the grains next to the sheet
  // (`near`), each in id order, gathered from every rank's own grains (a few values a grain of
  // those sets, not every grain's record). All ranks call it.
  void gather_row_measures(std::vector<double>& zone, std::vector<double>& near);
  // The whole sample's grains for which pred(i) holds of the world's grain i (all ranks
  // call it: a decomposed run counts every rank's own).
  template <class Pred>
  std::size_t count_grains(Pred&& pred) const {
    const auto& P = w.particles;
    std::size_t n = 0;
    for (std::size_t i = 0; i < P.size(); ++i) n += !(P.flags[i] & kGhost) && pred(i) ? 1 : 0;
    return domain ? domain.current->count_over_ranks(n) : n;
  }
  std::size_t grain_count() const { return grain_and_clump_counts(w)[0]; }

  void build();

  void start();

  // build(), then the newest valid checkpoint: the sheet and surcharge plate laid first.
  void resume();

  void prep_row(double stage, double unb);

  // Steps until the unbalanced force ratio falls below the settings' threshold. Resumes
  // where a checkpoint left it (stage_step).
  void settle(const std::string& stage, double stage_code);

  // Deposits layers over [x0, x1] until the surface there reaches `height`.
  void deposit_to(double height, double x0, double x1, const std::string& stage, double stage_code);

  // The sheet, its axis half a thickness above the foundation's top.
  void lay_sheet();

  // Foundation: deposited, trimmed flat at the run-out level, the trench excavated; then
  // the sheet is laid and the foundation held (a face that stands while the trench is
  // open).
  void foundation_phase();

  // The cover trimmed flat; the foundation released; the free face; the surcharge.
  void finish_fill();

  void consolidation_phase();

  void after_consolidation();

  // The plate on the cover, held at the surcharge pressure.
  void add_surcharge_plate();

  // End of the preparation: the anchoring zone, the analytic estimate, the initial
  // states, the output files of the pull; the clamp starts moving.
  void begin_pull();

  // The free end pulled horizontally at a constant rate.
  void pull_phase();

  // After a step of the pull: the clamp's displacement and tension, a history row when
  // one is due, the tension profiles the displacement has reached. Never stops the loop
  // (false): the pull ends at its displacement.
  bool record_pull(double d_record);

  void run_phases();
};

}  // namespace geodem
