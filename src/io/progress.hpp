// Progress on stderr for runs longer than a few seconds: stage, step, simulated
// time, ETA, unbalanced force. On a terminal the line is redrawn about twice a
// second; otherwise one line every 10 s at most. Silent with --quiet.
#pragma once

#include <chrono>
#include <string>

namespace geodem {

class Progress {
 public:
  explicit Progress(bool quiet);
  // fraction in [0, 1] of the whole run; extra: free text (unbalanced force...).
  void update(const std::string& stage, std::uint64_t step, double time, double fraction,
              const std::string& extra);
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  bool quiet_, tty_;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
  bool drew_ = false;
};

}  // namespace geodem
