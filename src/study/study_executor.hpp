// Runs the independent tests of a study: validates them all first, shares them among
// the MPI ranks and, on each rank, among worker threads (one run per worker, largest
// first), skips runs already finished by an earlier, interrupted invocation, shows the
// runs done and an ETA, and hands every rank all the runs' summaries.
//
// Each run lives in OUT/runs/ID/: its scenario.toml (re-runnable alone with `geodem
// run`), its history and preparation CSVs, and summary.json, written last and
// atomically. A run counts as finished when that summary exists, says "completed" and
// holds the same resolved scenario; anything else is run again.
#pragma once

#include <toml++/toml.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace geodem {

struct StudyRun {
  std::string id;        // folder name under OUT/runs/
  toml::table scenario;  // a complete lab scenario: triaxial, interface_shear or pullout
  double cost = 1.0;     // relative run time: the schedule and the ETA use it
};

struct StudyOptions {
  std::string out_dir = "out";
  std::string file;  // the study's scenario file, for messages
  bool quiet = false;
  int workers = 1;  // concurrent runs on this rank
};

class StudyExecutor {
 public:
  // Creates the output folder.
  explicit StudyExecutor(StudyOptions options);

  // Checks every scenario (InputError names the study file), then runs the unfinished
  // ones. Returns each run's summary, in the order given, on every rank; a run that
  // failed gives {"status": "failed" or "unstable", "error": message}.
  std::vector<nlohmann::json> run(const std::vector<StudyRun>& runs, const std::string& stage);

  // Totals over all calls, all ranks.
  std::size_t runs_done() const { return done_; }
  std::size_t runs_reused() const { return reused_; }
  // Particle-steps of the runs computed now (not reused), for the study's throughput.
  double particle_steps_computed() const { return particle_steps_; }
  const StudyOptions& options() const { return opt_; }

 private:
  StudyOptions opt_;
  std::size_t done_ = 0, reused_ = 0;
  double particle_steps_ = 0.0;
};

// Rank 0 writes the study's own files; the other ranks only run.
bool study_root();

}  // namespace geodem
