// A lab test spread over the ranks of mpirun (docs/parallel.md): the sample under test and the
// prepared sample every test starts from are each decomposed (scene/scene_domain.hpp), a
// checkpoint gathers both whole to rank 0, and a test begins from a copy of the prepared
// sample's domain as from a copy of its world. The runners that deposit layers (pull-out,
// interface shear) spread their world at its first layer (grains_added).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "base/error.hpp"
#include "io/interrupt.hpp"
#include "io/progress.hpp"
#include "io/run_checkpoints.hpp"
#include "lab/deposit_cache.hpp"
#include "lab/triaxial_settings.hpp"
#include "measure/measurements.hpp"
#include "scene/scene_domain.hpp"
#include "study/study_comm.hpp"

namespace geodem {

template <int D>
struct LabDomain {
  // This rank's part of the sample under test and of the prepared one; their keys and
  // contact history between a checkpoint's reading and the decomposition.
  std::shared_ptr<SlabDomain<D>> current, prepared;
  DomainCheckpoint<D> saved, saved_prepared;

  explicit operator bool() const { return current != nullptr; }

  // Spreads `w` (and `prep`, when given) over the ranks of mpirun, from a checkpoint's keys
  // and history when `resumed`; a decomposed run's checkpoint resumed in one process goes on as
  // a domain of one rank (the same bits).
  void decompose(World<D>& w, World<D>* prep, const std::string& file, const RunOptions& opt,
                 bool resumed) {
    if (!opt.decompose && !resumed) return;
    const bool local = !opt.decompose;
    current = decompose_world(w, file, resumed ? &saved : nullptr, local, opt.rebalance_every);
    if (prep)
      prepared = decompose_world(*prep, file, resumed ? &saved_prepared : nullptr, local,
                                 opt.rebalance_every);
    saved = saved_prepared = DomainCheckpoint<D>{};
  }
  // The triaxial kind's: as decompose(); slabs the compaction will make too thin are refused at
  // the start.
  void spread(World<D>& w, World<D>* prep, const TriaxialSettings& s, const RunOptions& opt,
              bool resumed) {
    if (!opt.decompose && !resumed) return;
    decompose(w, prep, s.file, opt, resumed);
    if (!resumed) refuse_slabs_too_thin_for_growth(w, s);
  }
  // Grains (and clumps) from `first_grain` (`first_clump`) on were appended by every rank alike
  // (a dropped layer): each rank keeps its own; a run over ranks is spread at its first layer.
  void grains_added(World<D>& w, std::size_t first_grain, std::size_t first_clump,
                    const std::string& file, const RunOptions& opt) {
    if (current)
      keep_own_added_grains(w, first_grain, first_clump);
    else
      decompose(w, nullptr, file, opt, false);
  }
  // A deposit cache (lab/deposit_cache.hpp) of a decomposed run holds the whole world gathered
  // on rank 0 and the keys and contact history of its domain, so that a run over any number of
  // ranks that loads it spreads it as a resumed checkpoint and goes on in the bits of a run that
  // deposited it itself. Its stage has a name of its own: a one-process run's deposit (grains
  // numbered and ordered otherwise) is never loaded by a decomposed run, nor the other way.
  static std::string deposit_stage(const std::string& stage, const RunOptions& opt) {
    return opt.decompose ? stage + "_ranks" : stage;
  }
  // The cache's file as every rank of the run found it: a file that one rank sees and another
  // does not yet (stored that moment by a run beside it) is a miss for all.
  static std::optional<Checkpoint> load_deposit(const DepositCache& cache, const RunOptions& opt) {
    std::optional<Checkpoint> c = cache.load();
    if (opt.decompose && !comm::group_all(c.has_value())) c.reset();
    return c;
  }
  // Stores the deposit: store(visit_domain) writes the cache on the rank that writes the run's
  // files, with visit_domain(StateWriter&) among the runner's state. All ranks call it.
  template <class Store>
  void store_deposit(World<D>& w, bool root, const RunOptions& opt, Store&& store) {
    if (!opt.decompose) return store([](StateWriter&) {});
    DomainWorldOnRank0<D> whole(w, current.get(), saved);
    if (root) store([this](StateWriter& a) { visit(a, false); });
  }
  // The domain's part of a loaded deposit (visit_domain's): read before the world, which
  // spread_deposit() then decomposes from it.
  void load_deposit_domain(StateReader& a, const RunOptions& opt) {
    if (opt.decompose) visit(a, false);
  }
  void spread_deposit(World<D>& w, const std::string& file, const RunOptions& opt) {
    if (opt.decompose) decompose(w, nullptr, file, opt, decomposed != 0);
  }

  // The compaction grows the radii until the grains fill the box, at most to a porosity of
  // 0.1 (discs) or 0.25 (spheres), denser than radius growth packs them: about g = ((1 -
  // n_min) / solid fraction now)^(1/D) times, and the ghost width with them. Slabs thinner than
  // that width are refused now rather than after the compaction's first minutes (on the
  // tests' 2D sample, g = 3.0 against the 2.8 the compaction reached).
  void refuse_slabs_too_thin_for_growth(const World<D>& w, const TriaxialSettings& s) const {
    double box = 1.0;
    for (int k = 0; k < D; ++k) box *= s.box[static_cast<std::size_t>(k)];
    const double solid = solid_volume(w) / box, densest = D == 2 ? 0.9 : 0.75;
    if (!(solid > 0.0) || solid >= densest) return;
    const double g = std::pow(densest / solid, 1.0 / D);
    // (a slab must be a ghost width across, and as much again as a clump's member may lie
    // from its centre: SlabDomain::thinnest_slab)
    const double width = (current->thinnest_slab() - current->skin()) * g + current->skin();
    const auto& cuts = current->cuts();
    // (a periodic cell's cuts are fractions of its width, and every slab has two neighbours;
    // the cell shrinks instead of the grains growing, to the same ratio)
    const bool ring = s.periodic && cuts.size() > 2;
    const double metres = s.periodic ? s.box[0] : 1.0;
    for (std::size_t q = ring ? 0 : 1; q + (ring ? 1 : 2) < cuts.size(); ++q)
      if ((cuts[q + 1] - cuts[q]) * metres < width)
        throw InputError(s.file, 0, "mpirun -n",
                         "the compaction will grow the grains up to about " + format_sig(g) +
                             " times: a slab must then be about " + format_sig(width) +
                             " m across (ghosts and clumps' reach), and one of " +
                             format_sig((cuts[q + 1] - cuts[q]) * metres) +
                             " m is too thin; use at most about " +
                             std::to_string(std::max(1, static_cast<int>(s.box[0] / width))) +
                             " ranks (docs/parallel.md)");
  }

  // The prepared sample was copied from the sample under test: its domain too.
  void keep_prepared(World<D>& prep) {
    if (current) prepared = current->copy(), prep.domain = prepared;
  }
  // A test starts from a copy of the prepared sample: its domain too.
  void start_from_prepared(World<D>& w) {
    if (prepared) current = prepared->copy(), w.domain = current;
  }

  // The runner's part of a checkpoint: whether decomposed, then the saved keys and history.
  template <class Archive>
  void visit(Archive& a, bool for_prepared) {
    if (for_prepared) {
      if (decomposed) saved_prepared.visit(a);
      return;
    }
    if constexpr (!Archive::kLoading) decomposed = current ? 1 : 0;
    a(decomposed);
    if (decomposed) saved.visit(a);
  }
  std::uint8_t decomposed = 0;  // the checkpoint written or read is a decomposed run's

  // After a whole step of a decomposed run: the ranks stop together on a signal, at a step
  // they agree on, and a checkpoint is written when due (wall-clock ones: any rank's). While
  // `write` runs (on every rank; rank 0 writes the file), rank 0's worlds hold the whole
  // samples. Throws Interrupted on a signal.
  template <class Write>
  void after_step(World<D>& w, World<D>* prep, RunCheckpoints& checkpoints,
                  std::uint64_t total_steps, Write&& write) {
    const bool signal = signalled(total_steps);
    const bool due = checkpoints.due(total_steps);
    if (signal || (checkpoints.spec().enabled() ? current->any_rank(due) : due)) {
      DomainWorldOnRank0<D> whole(w, current.get(), saved);
      std::optional<DomainWorldOnRank0<D>> whole_prepared;
      if (prep) whole_prepared.emplace(*prep, prepared.get(), saved_prepared);
      write();
    }
    saved = saved_prepared = DomainCheckpoint<D>{};
    if (signal) throw Interrupted{interrupt_signal() ? interrupt_signal() : 15, checkpoints.last()};
  }

  // Whether a signal reached any rank (asked every 64 steps: the ranks agree on the step).
  bool signalled(std::uint64_t total_steps) {
    return total_steps % 64 == 0 && current->any_rank(interrupt_signal() != 0);
  }
  // Closes a step of a run without checkpoints (io/step_loop.hpp): a signal throws Interrupted,
  // on every rank of a decomposed run at the same step.
  bool stop_on_signal(std::uint64_t total_steps) {
    if (!current) return stopped_by_signal();
    if (signalled(total_steps)) throw Interrupted{interrupt_signal() ? interrupt_signal() : 15, ""};
    return false;
  }

  // The timing of summary.json: the whole sample's grains and rate (rank 0's times).
  void add_timing(nlohmann::json& timing, const World<D>& w, std::uint64_t steps) const {
    const auto grains = static_cast<double>(current->count_over_ranks(current->owned(w)));
    const double wall_s = timing["wall_s"].get<double>();
    timing["ranks"] = current->ranks();
    timing["particles"] = static_cast<std::uint64_t>(grains);
    timing["particle_steps_per_s"] =
        wall_s > 0.0 ? static_cast<double>(steps) * grains / wall_s : 0.0;
  }
};

// Runs `body`; an InputError of the decomposition met where no file is known (a list build's
// check of the slabs) names the scenario's `file` and "mpirun -n".
template <class Body>
decltype(auto) naming_decomposition_errors(const std::string& file, Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    throw InputError(file, 0, "mpirun -n", e.detail());
  }
}

}  // namespace geodem
