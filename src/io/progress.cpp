#include "io/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace geodem {

std::string format_sig(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string format_duration(double s) {
  char buf[48];
  s = std::max(0.0, s);
  if (s < 100.0)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600.0)
    std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(s / 60.0),
                  static_cast<int>(std::fmod(s, 60.0)));
  else
    std::snprintf(buf, sizeof buf, "%d h %02d min", static_cast<int>(s / 3600.0),
                  static_cast<int>(std::fmod(s, 3600.0) / 60.0));
  return buf;
}

Progress::Progress(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0) {}

namespace {
// Time left at the rate (f - f0) / dt, once the stage has moved enough to measure it.
double eta(double f, double f0, double dt) {
  if (f >= 1.0) return 0.0;
  if (f - f0 < 1e-3 || dt < 1.0) return -1.0;
  return (1.0 - f) * dt / (f - f0);
}
}  // namespace

std::string Progress::line(const std::string& stage, std::uint64_t step, double time,
                           double stage_fraction, const std::string& extra, double run_fraction,
                           double now_s) {
  if (stage != stage_) {
    stage_ = stage;
    stage_start_s_ = now_s;
    stage_f0_ = std::max(stage_fraction, 0.0);
    run_f0_ = std::max(run_fraction, 0.0);
  }
  const double in_stage = now_s - stage_start_s_;
  // "<lead>42.1 %, ETA 35 s": a percentage with `format`, and the ETA once measurable.
  auto share = [&](const char* format, double f, double f0) {
    char buf[48];
    std::snprintf(buf, sizeof buf, format, 100.0 * std::min(f, 1.0));
    const double left = eta(f, f0, in_stage);
    return std::string(buf) + (left >= 0.0 ? ", ETA " + format_duration(left) : "");
  };
  std::string out = stage + ":";
  if (stage_fraction >= 0.0) out += share(" %.1f %%", stage_fraction, stage_f0_);
  if (!extra.empty()) out += (stage_fraction >= 0.0 ? ", " : " ") + extra;
  if (run_fraction >= 0.0) out += share("; run %.0f %%", run_fraction, run_f0_);
  out += "; elapsed " + format_duration(now_s) + ", step " + std::to_string(step) + ", t " +
         format_sig(time) + " s";
  return out;
}

void Progress::update(const std::string& stage, std::uint64_t step, double time,
                      double stage_fraction, const std::string& extra, double run_fraction) {
  if (quiet_) return;
  const auto now = Clock::now();
  const double since_start = std::chrono::duration<double>(now - start_).count();
  const double since_last = std::chrono::duration<double>(now - last_).count();
  const bool due = since_start >= 2.0 && since_last >= (tty_ ? 0.5 : 10.0);
  if (!due && stage == stage_) return;
  // Built for a new stage even when not printed: the stage's rate is measured from here.
  const std::string text =
      line(stage, step, time, stage_fraction, extra, run_fraction, since_start);
  if (!due) return;
  last_ = now;
  std::fprintf(stderr, "%s%s%s", tty_ ? "\r\033[K" : "", text.c_str(), tty_ ? "" : "\n");
  std::fflush(stderr);
  drew_ = true;
}

void Progress::finish() {
  if (!quiet_ && tty_ && drew_) std::fprintf(stderr, "\n");
}

}  // namespace geodem
