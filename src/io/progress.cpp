#include "io/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace geodem {

Progress::Progress(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0) {}

void Progress::update(const std::string& stage, std::uint64_t step, double time, double fraction,
                      const std::string& extra) {
  if (quiet_) return;
  const auto now = Clock::now();
  const double since_start = std::chrono::duration<double>(now - start_).count();
  const double since_last = std::chrono::duration<double>(now - last_).count();
  if (since_start < 2.0 || since_last < (tty_ ? 0.5 : 10.0)) return;
  last_ = now;
  const double eta = fraction > 1e-6 ? since_start * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "%s%s: step %llu, t = %.4g s, %3.0f %%, ETA %.0f s%s%s%s",
               tty_ ? "\r\033[K" : "", stage.c_str(), static_cast<unsigned long long>(step), time,
               100.0 * fraction, eta, extra.empty() ? "" : ", ", extra.c_str(), tty_ ? "" : "\n");
  std::fflush(stderr);
  drew_ = true;
}

void Progress::finish() {
  if (!quiet_ && tty_ && drew_) std::fprintf(stderr, "\n");
}

}  // namespace geodem
