#include "study/study_output.hpp"

#include <algorithm>
#include <limits>

#include "study/study_comm.hpp"

namespace geodem {

nlohmann::json failed_runs(const std::vector<StudyRun>& runs,
                           const std::vector<nlohmann::json>& summaries) {
  nlohmann::json failed = nlohmann::json::array();
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (!run_completed(summaries[i]))
      failed.push_back({{"id", runs[i].id},
                        {"status", summaries[i].value("status", "failed")},
                        {"error", summaries[i].value("error", "")}});
  return failed;
}

nlohmann::json study_timing(const std::vector<nlohmann::json>& summaries, double wall_s,
                            const StudyExecutor& executor) {
  double steps = 0.0, particles = 0.0;
  for (const auto& s : summaries) {
    if (!s.contains("timing")) continue;
    const auto& t = s["timing"];
    steps += t.value("steps", 0.0);
    particles = std::max(particles, t.value("particles", 0.0));
  }
  nlohmann::json t;
  t["wall_s"] = wall_s;
  t["steps"] = steps;
  t["particles"] = particles;
  // Runs reused from an earlier invocation took no time now: only the runs computed now
  // count in the throughput.
  t["particle_steps_per_s"] = wall_s > 0.0 ? executor.particle_steps_computed() / wall_s : 0.0;
  t["threads"] = executor.options().workers;
  t["ranks"] = comm::size();
  t["ranks_per_run"] = comm::group_size();
  t["runs_done"] = executor.runs_done();
  t["runs_reused"] = executor.runs_reused();
  return t;
}

double run_result(const nlohmann::json& summary, const std::string& key) {
  if (!summary.contains("results")) return std::numeric_limits<double>::quiet_NaN();
  const auto& r = summary["results"];
  if (r.contains(key) && r[key].is_number()) return r[key].get<double>();
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace geodem
