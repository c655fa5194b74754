// A run's checkpoints, for every scenario kind that writes them: when one is due (every
// so many steps or wall-clock seconds, and on SIGINT/SIGTERM), writing it, and finding
// the one to resume from. The runner supplies its own state and the world's
// (io/checkpoint.hpp has the file format).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/state_archive.hpp"
#include "io/checkpoint.hpp"
#include "io/interrupt.hpp"
#include "io/output_files.hpp"

namespace geodem {

class RunCheckpoints {
 public:
  RunCheckpoints(std::string kind, int dimension, const nlohmann::json& resolved,
                 std::string out_dir, CheckpointSpec spec)
      : kind_(std::move(kind)),
        dimension_(dimension),
        resolved_(resolved),
        out_dir_(std::move(out_dir)),
        spec_(spec) {}

  // The newest valid checkpoint of the output folder (damaged ones are reported on stderr
  // and skipped), checked against this run: same kind and dimension, and settings that
  // differ only under the keys of `may_change` (besides [checkpoint]). Checkpoint files
  // after it are deleted. Problems are InputErrors naming `scenario_file`. The ranks of a
  // decomposed run other than rank 0 read it too, as not `primary`: they neither delete nor
  // report.
  Checkpoint resume(const std::string& scenario_file, const std::vector<std::string>& may_change,
                    bool primary = true);

  // Wall-clock seconds of the whole run: since this object was made, plus those before the
  // checkpoint resumed from (resume_clock). Runners save it in their state.
  double elapsed() const {
    return before_ + std::chrono::duration<double>(Clock::now() - start_).count();
  }
  // On resuming: the run's wall time up to its checkpoint; the periodic count restarts there.
  void resume_clock(double before_s) {
    before_ = last_wall_ = before_s;
    start_ = Clock::now();
  }

  // A periodic checkpoint is due after this step. `step` counts the steps of the whole run
  // (it names and orders the files, so it must grow: a lab test's world restarts its own
  // count with each confining stress).
  bool due(std::uint64_t step) const {
    return (spec_.every_steps > 0 && step % spec_.every_steps == 0) ||
           (spec_.every_seconds > 0.0 && elapsed() - last_wall_ >= spec_.every_seconds);
  }

  // The CSV files whose row counts the runner saves in its checkpoints. write() puts
  // their rows on disk before the checkpoint that counts them (crash consistency: a
  // checkpoint never counts a row a crash can lose).
  void outputs(std::vector<HistoryCsv*> files) { outputs_ = std::move(files); }

  // Writes a checkpoint, after the outputs' rows and the output folder are on disk, with
  // the world streamed into the file (no copy of the state in memory while a checkpoint is
  // written); returns its path. save(StateWriter& runner, StateWriter& world) is called three
  // times (the runner's part kept from the first, the world's counted, then streamed) and
  // must give the same bytes each time.
  template <class Save>
  const std::string& write_with(std::uint64_t step, double time, Save&& save) {
    auto discard = [](const char*, std::size_t) {};
    StateWriter runner, no_world(discard);
    save(runner, no_world);
    return write_streamed(step, time, std::move(runner.bytes()), [&](StateWriter& world) {
      StateWriter no_runner(discard);
      save(no_runner, world);
    });
  }

  // For run loops after a whole step: writes a checkpoint when one is due or a signal has
  // come, then stops on the signal (throws Interrupted naming the checkpoint).
  // save(StateWriter& runner, StateWriter& world) fills the two parts.
  template <class Save>
  void after_step(std::uint64_t step, double time, Save&& save) {
    const int signal = interrupt_signal();
    if (signal || due(step)) write_with(step, time, save);
    if (signal) throw Interrupted{signal, last_};
  }

  // An instability's message with the checkpoint to go back to, when there is one.
  std::string diagnosis(const std::string& what) const {
    return last_.empty() ? what
                         : what + "; last checkpoint: " + last_ + " (step " +
                               std::to_string(last_step_) + ")";
  }

  const std::string& last() const { return last_; }
  std::uint64_t last_step() const { return last_step_; }
  const CheckpointSpec& spec() const { return spec_; }

 private:
  const std::string& write_streamed(std::uint64_t step, double time, std::string runner,
                                    const std::function<void(StateWriter&)>& save_world);
  using Clock = std::chrono::steady_clock;
  std::string kind_;
  int dimension_;
  const nlohmann::json& resolved_;
  std::string out_dir_;
  CheckpointSpec spec_;
  std::vector<HistoryCsv*> outputs_;
  std::string last_;
  std::uint64_t last_step_ = 0;
  double last_wall_ = 0.0;  // elapsed() at the last checkpoint
  double before_ = 0.0;
  Clock::time_point start_ = Clock::now();
};

// A JSON value in a state archive, as its text (doubles keep all their digits).
template <class Archive>
void archive_json(Archive& a, nlohmann::json& j) {
  if constexpr (Archive::kLoading) {
    std::string text;
    a(text);
    j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded()) throw CheckpointError("unreadable results in the checkpoint");
  } else {
    a(j.dump());
  }
}

}  // namespace geodem
