// The course shared by the lab runners (triaxial, pull-out), which are phase machines:
// build from the scenario, start afresh or resume from the newest checkpoint, run the
// phases. An instability leaves an "unstable" summary naming the last checkpoint.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "base/error.hpp"
#include "io/interrupt.hpp"
#include "io/run_output.hpp"

namespace geodem {

// Runner: build(), start(), resume(), run_phases(), progress, checkpoints (RunCheckpoints).
template <class Runner>
void run_lab_phases(Runner& r, const std::string& kind, const nlohmann::json& resolved,
                    const RunOptions& opt) {
  r.build();
  if (opt.resume)
    r.resume();
  else
    r.start();
  try {
    r.run_phases();
  } catch (const InstabilityError& e) {
    const std::string why = r.checkpoints.diagnosis(
        std::string(e.what()) + " [" + kind +
        " tests take the automatic time step: time.safety (default 0.8); the soil's young]");
    if (opt.primary)
      write_stopped_summary(opt.out_dir, kind, resolved, "unstable", why, r.checkpoints.last(),
                            opt.threads);
    throw InstabilityError(why);
  }
  r.progress.finish();
}

// Runs a lab runner's `body`; a run stopped by a signal leaves an "interrupted" summary
// naming the checkpoint to resume from (none for kinds without checkpoints).
template <class Body>
nlohmann::json summarise_interruption(const std::string& kind, const nlohmann::json& resolved,
                                      const RunOptions& opt, Body&& body) {
  try {
    return body();
  } catch (const Interrupted& i) {
    if (opt.primary)
      write_stopped_summary(opt.out_dir, kind, resolved, "interrupted",
                            "signal " + std::to_string(i.signal), i.checkpoint, opt.threads);
    throw;
  }
}

}  // namespace geodem
