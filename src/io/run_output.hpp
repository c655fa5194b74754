// The pieces every scenario kind shares: the output folder, summary.json, VTK
// series with their .pvd index, and the PNG plots made by python/geodem_plot.py.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "base/state_archive.hpp"
#include "io/vtk_writer.hpp"
#include "world/world.hpp"

namespace geodem {

struct RunOptions {
  std::string out_dir = "out";
  bool quiet = false;
  int threads = 1;
  bool resume = false;  // continue from the newest valid checkpoint in out_dir
  // One model over the ranks of mpirun (docs/parallel.md): the runner decomposes its world.
  bool decompose = false;
  // Writes the outputs: false on the ranks of a decomposed run other than rank 0.
  bool primary = true;
  // A decomposed run weighs its ranks' work every this many list builds and moves the cuts
  // when it is uneven (SlabDomain::rebalance_every; 0: never).
  int rebalance_every = 10;
};

// Creates DIR and DIR/vtk (exit code 1 on failure).
void prepare_output_dir(const std::string& dir);

// The output folder of a new run (not a resume): refused, with a message saying why and
// what to do, when it holds files; with `overwrite`, a folder that holds an earlier geodem
// run (summary.json, history.csv, checkpoint/...) is emptied first, so that no file of the
// earlier run (VTK frames, CSVs, plots) stays beside the new one. Returns "" when the
// folder may be written; never empties a folder that is not a run's.
std::string claim_output_dir(const std::string& dir, bool overwrite);

// summary.json: {"kind", "geodem_version", "status", "scenario", "results", "timing"}.
void write_summary(const std::string& dir, const nlohmann::json& summary);

// Assembles summary.json from its parts, writes it and returns it.
nlohmann::json write_run_summary(const std::string& dir, const std::string& kind,
                                 const std::string& status, const nlohmann::json& scenario,
                                 const nlohmann::json& results, const nlohmann::json& timing);

// summary.json of a lab test that stopped before its end: status "interrupted" (a signal)
// or "unstable", the reason, and the last checkpoint written (resume with --resume); the
// history and VTK files written so far are whole.
void write_stopped_summary(const std::string& dir, const std::string& kind,
                           const nlohmann::json& scenario, const std::string& status,
                           const std::string& reason, const std::string& checkpoint, int threads);

// Timing block of summary.json from a world's counters.
template <int D>
nlohmann::json timing_json(const World<D>& world, double wall_s, std::uint64_t steps, int threads);

// Snapshots of grains and walls, indexed in vtk/particles.pvd.
template <int D>
class VtkSeries {
 public:
  explicit VtkSeries(const std::string& dir) : dir_(dir), pvd_(dir + "/vtk/particles.pvd") {}
  void write(const World<D>& world);
  int count() const { return count_; }
  // Also write the contact network (force chains) of each frame.
  void with_contacts(bool on) { contacts_ = on; }
  // Also each grain's displacement since `reference` (positions by id; not owned; null: none).
  void with_reference(const std::vector<typename Dim<D>::Vec>* reference) {
    reference_ = reference;
  }
  // Checkpoints: the frames written so far. restore() also deletes the files of frames
  // written after the checkpoint and rewrites the index, so that a resumed run's series
  // is the one an uninterrupted run writes.
  void save(StateWriter& out) const;
  // (`primary`: this process deletes and rewrites; the other ranks of a decomposed run only read)
  void restore(StateReader& in, bool primary = true);

 private:
  std::string dir_;
  PvdIndex pvd_;
  int count_ = 0;
  bool contacts_ = false;
  const std::vector<typename Dim<D>::Vec>* reference_ = nullptr;
};

// The version string.
const char* version();

}  // namespace geodem
