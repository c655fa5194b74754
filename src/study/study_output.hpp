// What every study writes besides its own tables: the list of failed runs, the timing
// block (totals over the runs), and the runs' flat results.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "study/study_executor.hpp"

namespace geodem {

inline bool run_completed(const nlohmann::json& summary) {
  return summary.value("status", "") == "completed";
}

// {"id": ..., "status": ..., "error": ...} for each run that did not complete.
nlohmann::json failed_runs(const std::vector<StudyRun>& runs,
                           const std::vector<nlohmann::json>& summaries);

// summary.json "timing": wall time of the study, steps summed over the runs (done now
// and before), the largest run's particle count, the particle-steps per second of the
// runs computed now, workers per rank, ranks, runs done and reused.
nlohmann::json study_timing(const std::vector<nlohmann::json>& summaries, double wall_s,
                            const StudyExecutor& executor);

// A result of a run's (single) test, as a number; NaN when absent.
double run_result(const nlohmann::json& summary, const std::string& key);

}  // namespace geodem
