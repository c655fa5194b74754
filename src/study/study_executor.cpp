#include "study/study_executor.hpp"
#include "base/text.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <numeric>
#include <sstream>
#include <thread>

#include "base/error.hpp"
#include "io/checkpoint.hpp"
#include "io/output_files.hpp"
#include "lab/run_interface_shear.hpp"
#include "lab/run_pullout.hpp"
#include "lab/run_triaxial.hpp"
#include "lab/triaxial_settings.hpp"
#include "study/study_comm.hpp"

namespace geodem {

namespace {

using Clock = std::chrono::steady_clock;

// A finished run's summary, or null when the run must be (re)done.
nlohmann::json finished_summary(const std::string& dir, const nlohmann::json& resolved) {
  std::ifstream in(cat(dir, "/summary.json"));
  if (!in) return nullptr;
  try {
    nlohmann::json s = nlohmann::json::parse(in);
    if (s.value("status", "") == "completed" && s.contains("scenario") && s["scenario"] == resolved)
      return s;
  } catch (const nlohmann::json::exception&) {
  }
  return nullptr;
}

// Runs a study's test. When the study asks for checkpoints (its base scenario's
// [checkpoint]), a run that was stopped with the study continues from its newest checkpoint,
// and one whose checkpoints do not fit (another scenario's, damaged) starts afresh. A
// finished run's checkpoints are deleted: it is reused from its summary.
template <class Settings, class Run>
nlohmann::json run_or_resume(const Settings& settings, RunOptions ro, Run run) {
  const std::string folder = checkpoint_folder(ro.out_dir);
  std::error_code ec;
  ro.resume = settings.checkpoint.enabled() && std::filesystem::exists(folder, ec) &&
              !std::filesystem::is_empty(folder, ec);
  nlohmann::json summary;
  try {
    summary = run(settings, ro);
  } catch (const InputError&) {
    if (!ro.resume) throw;
    std::filesystem::remove_all(folder, ec);
    ro.resume = false;
    summary = run(settings, ro);
  }
  std::filesystem::remove_all(folder, ec);
  return summary;
}

// A study's run, read and checked: its resolved scenario and how to run it. The lab
// kinds a study can run: triaxial, interface_shear, pullout.
struct CheckedRun {
  nlohmann::json resolved;
  std::function<nlohmann::json(const RunOptions&)> run;
};

CheckedRun check_run(const toml::table& scenario, const std::string& file) {
  const std::string kind = scenario["kind"].value_or(std::string("triaxial"));
  if (kind == "interface_shear") {
    auto s = std::make_shared<InterfaceShearSettings>(read_interface_shear(scenario, file));
    return {s->resolved, [s](const RunOptions& ro) { return run_interface_shear(*s, ro); }};
  }
  if (kind == "pullout") {
    auto s = std::make_shared<PulloutSettings>(read_pullout(scenario, file));
    return {s->resolved, [s](const RunOptions& ro) { return run_or_resume(*s, ro, run_pullout); }};
  }
  auto s = std::make_shared<TriaxialSettings>(read_triaxial(scenario, file));
  return {s->resolved, [s](const RunOptions& ro) { return run_or_resume(*s, ro, run_triaxial); }};
}

std::string format_duration(double s) {
  char buf[32];
  if (s < 120.0)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 7200.0)
    std::snprintf(buf, sizeof buf, "%.1f min", s / 60.0);
  else
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600.0);
  return buf;
}

// "stage: 5/12 runs done (2 reused), 1 failed, ETA 3.2 min" on stderr: redrawn on a
// terminal, one line every 10 s otherwise; rank 0 speaks for its share.
class StudyProgress {
 public:
  StudyProgress(bool quiet, std::string stage, std::size_t total, double total_cost)
      : quiet_(quiet || !study_root()),
        tty_(isatty(STDERR_FILENO) != 0),
        stage_(std::move(stage)),
        total_(total),
        total_cost_(total_cost) {}

  void add(double cost, bool reused, bool failed) {
    std::lock_guard<std::mutex> lock(m_);
    ++done_;
    if (reused) {
      ++reused_;
      total_cost_ -= cost;  // costs nothing now: not part of the ETA
    } else {
      done_cost_ += cost;
    }
    if (failed) ++failed_;
    draw(false);
  }

  void finish() {
    std::lock_guard<std::mutex> lock(m_);
    draw(true);
    if (!quiet_ && tty_) std::fprintf(stderr, "\n");
  }

 private:
  void draw(bool last) {
    if (quiet_) return;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double since = std::chrono::duration<double>(now - last_).count();
    if (!last && since < (tty_ ? 0.5 : 10.0)) return;
    last_ = now;
    std::string eta;
    if (done_cost_ > 0.0 && done_ < total_)
      eta = cat(", ETA ", format_duration(elapsed * (total_cost_ - done_cost_) / done_cost_));
    std::string share = comm::size() > 1 ? cat(" on rank 0 of ", comm::size()) : "";
    std::fprintf(stderr, "%s%s: %zu/%zu runs done%s%s%s, elapsed %s%s%s", tty_ ? "\r\033[K" : "",
                 stage_.c_str(), done_, total_, share.c_str(),
                 reused_ ? cat(" (", reused_, " from before)").c_str() : "",
                 failed_ ? cat(", ", failed_, " failed").c_str() : "",
                 format_duration(elapsed).c_str(), eta.c_str(), tty_ ? "" : "\n");
    std::fflush(stderr);
  }

  bool quiet_, tty_;
  std::string stage_;
  std::size_t total_, done_ = 0, reused_ = 0, failed_ = 0;
  double total_cost_, done_cost_ = 0.0;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
  std::mutex m_;
};

// Largest runs first, each to the least loaded rank (group of ranks with --ranks-per-run): the
// same share on every rank of a group.
std::vector<std::size_t> my_share(const std::vector<StudyRun>& runs) {
  std::vector<std::size_t> order(runs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return runs[a].cost > runs[b].cost; });
  std::vector<double> load(static_cast<std::size_t>(comm::groups()), 0.0);
  std::vector<std::size_t> mine;
  for (std::size_t i : order) {
    const auto r =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[r] += runs[i].cost;
    if (static_cast<int>(r) == comm::group()) mine.push_back(i);
  }
  return mine;
}

}  // namespace

bool study_root() {
  return comm::rank() == 0;
}

StudyExecutor::StudyExecutor(StudyOptions options) : opt_(std::move(options)) {
  std::error_code ec;
  std::filesystem::create_directories(cat(opt_.out_dir, "/runs"), ec);
  if (ec)
    throw std::runtime_error(cat("cannot create output folder ", opt_.out_dir, ": ", ec.message()));
}

std::vector<nlohmann::json> StudyExecutor::run(const std::vector<StudyRun>& runs,
                                               const std::string& stage) {
  // Every scenario is checked before anything runs (all ranks, so all fail alike).
  std::vector<CheckedRun> settings;
  settings.reserve(runs.size());
  for (const auto& r : runs) settings.push_back(check_run(r.scenario, opt_.file));
  // A group of ranks runs its runs one at a time, each spread over the group's ranks (and
  // `workers` threads in each); the group's first rank writes the run's files.
  const bool grouped = comm::group_size() > 1;
  const bool writes = comm::group_rank() == 0;
  const std::vector<std::size_t> mine = my_share(runs);
  double share_cost = 0.0;
  for (std::size_t i : mine) share_cost += runs[i].cost;
  StudyProgress progress(opt_.quiet, stage, mine.size(), share_cost);
  std::vector<nlohmann::json> results(runs.size());
  std::vector<char> reused(runs.size(), 0);
  std::atomic<std::size_t> next{0};

  auto work = [&] {
    for (;;) {
      const std::size_t k = next.fetch_add(1);
      if (k >= mine.size()) return;
      const std::size_t i = mine[k];
      const std::string dir = cat(opt_.out_dir, "/runs/", runs[i].id);
      nlohmann::json summary = finished_summary(dir, settings[i].resolved);
      const bool from_before = !summary.is_null();
      if (!from_before) {
        try {
          std::filesystem::create_directories(dir);
          std::ostringstream toml_text;
          toml_text << "# run " << runs[i].id << " of the study " << opt_.file
                    << "; re-run alone with: geodem run scenario.toml\n"
                    << runs[i].scenario << "\n";
          if (writes) write_file_atomic(cat(dir, "/scenario.toml"), toml_text.str());
          RunOptions ro;
          ro.out_dir = dir;
          ro.quiet = true;
          ro.decompose = grouped;
          ro.primary = writes;
          if (grouped) ro.threads = opt_.workers;
          summary = settings[i].run(ro);
          std::error_code ec;
          if (writes) std::filesystem::remove(cat(dir, "/vtk"), ec);  // empty: no VTK
        } catch (const InstabilityError& e) {
          summary = {{"status", "unstable"}, {"error", e.what()}};
        } catch (const std::exception& e) {
          summary = {{"status", "failed"}, {"error", e.what()}};
        }
      }
      results[i] = std::move(summary);
      reused[i] = from_before ? 1 : 0;
      progress.add(runs[i].cost, from_before, results[i].value("status", "") != "completed");
    }
  };
  const int workers =
      grouped ? 1 : std::max(1, std::min<int>(opt_.workers, static_cast<int>(mine.size())));
  {
    std::vector<std::jthread> pool;
    for (int t = 1; t < workers; ++t) pool.emplace_back(work);
    work();
  }
  progress.finish();

  // Exchange: every rank (the first of each group) sends {index: summary} for its share, and
  // receives all.
  nlohmann::json part = nlohmann::json::object();
  for (std::size_t i : writes ? mine : std::vector<std::size_t>{})
    part[std::to_string(i)] = {{"summary", results[i]}, {"reused", reused[i] != 0}};
  for (const std::string& p : comm::all_gather(part.dump())) {
    const nlohmann::json received = nlohmann::json::parse(p);
    for (const auto& [key, v] : received.items()) {
      const std::size_t i = std::stoul(key);
      results[i] = v["summary"];
      if (v["reused"].get<bool>()) {
        ++reused_;
      } else if (results[i].contains("timing")) {
        const auto& t = results[i]["timing"];
        particle_steps_ += t.value("particle_steps_per_s", 0.0) * t.value("wall_s", 0.0);
      }
      ++done_;
    }
  }
  return results;
}

}  // namespace geodem
