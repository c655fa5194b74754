#include "io/run_checkpoints.hpp"

#include <algorithm>
#include <cstdio>

#include "base/error.hpp"

namespace geodem {

Checkpoint RunCheckpoints::resume(const std::string& scenario_file,
                                  const std::vector<std::string>& may_change, bool primary) {
  std::vector<std::string> skipped;
  Checkpoint c;
  try {
    c = load_latest_checkpoint(out_dir_, &skipped);
  } catch (const CheckpointError& e) {
    throw InputError(scenario_file, 0, "", std::string("cannot resume: ") + e.what());
  }
  for (const auto& why : skipped)
    if (primary) std::fprintf(stderr, "warning: skipped checkpoint %s\n", why.c_str());
  if (c.kind != kind_ || c.dimension != dimension_)
    throw InputError(scenario_file, 0, "kind",
                     "cannot resume: " + c.path + " is a " + std::to_string(c.dimension) + "D '" +
                         c.kind + "' run's checkpoint");
  nlohmann::json saved = nlohmann::json::parse(c.scenario, nullptr, false);
  if (saved.is_discarded())
    throw InputError(scenario_file, 0, "", "cannot resume: unreadable settings in " + c.path);
  std::vector<std::string> free = may_change;
  free.push_back("checkpoint");
  std::string allowed;
  for (const auto& f : free) allowed += (allowed.empty() ? "" : ", ") + f;
  for (const auto& op : nlohmann::json::diff(saved, resolved_)) {
    const std::string path = op["path"].get<std::string>();
    std::string key = path.substr(1);
    std::replace(key.begin(), key.end(), '/', '.');
    const bool may = std::any_of(free.begin(), free.end(), [&](const std::string& f) {
      return key == f || key.rfind(f + ".", 0) == 0;
    });
    if (may || key.empty() || key == "file") continue;
    throw InputError(scenario_file, 0, key,
                     "differs from the setting of the run being resumed (" + c.path +
                         "); only these may change: " + allowed);
  }
  if (!primary) return c;
  discard_checkpoints_after(out_dir_, c.step);
  std::fprintf(stderr, "resuming from %s (step %llu, t = %g s)\n", c.path.c_str(),
               static_cast<unsigned long long>(c.step), c.time);
  return c;
}

const std::string& RunCheckpoints::write_streamed(
    std::uint64_t step, double time, std::string runner,
    const std::function<void(StateWriter&)>& save_world) {
  // The order that makes a crash at any moment recoverable: every row the checkpoint
  // counts, and every file renamed into the folder (VTK frames, the .pvd), on disk first;
  // then the checkpoint, itself written aside and renamed.
  for (HistoryCsv* f : outputs_) f->sync();
  sync_to_disk(out_dir_, true);
  sync_to_disk(out_dir_ + "/vtk", true);
  Checkpoint c{kind_, dimension_, step, time, resolved_.dump(), std::move(runner), "", ""};
  last_ = write_checkpoint(out_dir_, c, spec_.keep, save_world);
  last_step_ = step;
  last_wall_ = elapsed();
  return last_;
}

}  // namespace geodem
