// Progress on stderr for runs longer than a few seconds: the stage, how far it is (a
// fraction of the stage, or the distance to its stop criterion when the stage ends on
// one), the stage's ETA from its own rate since it began, the run's ETA when the runner
// knows its whole course, the elapsed time, step and simulated time. On a terminal the
// line is redrawn about twice a second; otherwise one line every 10 s at most. Silent
// with --quiet.
#pragma once

#include <chrono>
#include <string>

namespace geodem {

// A value for a progress line: 4 significant digits ("1.403e+05", "0.0123").
std::string format_sig(double v);

// "45 s", "3 min 12 s", "2 h 05 min".
std::string format_duration(double seconds);

class Progress {
 public:
  explicit Progress(bool quiet);
  // stage_fraction: of the stage in [0, 1], or < 0 when the stage ends on a criterion
  // (then `extra` says how far it is from it); run_fraction: of the whole run, or < 0 when
  // unknown. The ETAs come from the rates since the stage began (a stage's name starts
  // it), so that a long preparation does not skew the estimate of what follows.
  void update(const std::string& stage, std::uint64_t step, double time, double stage_fraction,
              const std::string& extra, double run_fraction = -1.0);
  void finish();

  // The line update() would print (no terminal control), for tests.
  std::string line(const std::string& stage, std::uint64_t step, double time, double stage_fraction,
                   const std::string& extra, double run_fraction, double now_s);

 private:
  using Clock = std::chrono::steady_clock;
  bool quiet_, tty_;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
  bool drew_ = false;
  std::string stage_;  // the stage in progress, and where it and the run stood when it began
  double stage_start_s_ = 0.0, stage_f0_ = 0.0, run_f0_ = 0.0;
};

}  // namespace geodem
