// SIGINT and SIGTERM during a run: the handler only notes the signal; the run loop sees
// it after the step in progress, writes a checkpoint and its outputs, and the program
// exits with 128 + the signal number (130, 143). A second signal ends the program at once.
#pragma once

#include <string>

namespace geodem {

// Installs the handlers (idempotent).
void install_interrupt_handlers();

// The signal received (SIGINT, SIGTERM), or 0.
int interrupt_signal();

// Thrown by a run loop that stopped on a signal, after its outputs are written.
struct Interrupted {
  int signal;
  std::string checkpoint;  // path of the checkpoint written, or empty
};

// For run loops without checkpoints (lab tests): after a whole step, stop on a signal.
// The close of a step loop (io/step_loop.hpp) for a run without checkpoints: a signal
// throws, so it never returns true.
inline bool stopped_by_signal() {
  if (const int sig = interrupt_signal()) throw Interrupted{sig, ""};
  return false;
}

}  // namespace geodem
