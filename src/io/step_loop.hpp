// The step loop every runner drives its world with (scenes, the lab tests' phases): run
// until, record every, checkpoint when due, stop on a signal. The runner says what each
// of these means for it; the loop fixes their order, which checkpoints and resumed runs rely
// on: a checkpoint closes a step whose records are written, and a step that meets a stop
// criterion ends its loop before any checkpoint (a resumed run starts after the loop).
#pragma once

#include <cstdint>

#include "world/step.hpp"
#include "world/world.hpp"

namespace geodem {

// Steps `w` while more() holds. Each step is measured (stress sums, contact counts) when
// measure() says so, then counted in `steps` (the run's own count, which names
// checkpoints); then record() writes what is due and returns true to stop the loop there;
// else close() writes a checkpoint when one is due and returns true to stop (a signal).
// Returns true when record() or close() stopped the loop, false when more() ran out.
template <int D, class More, class Measure, class Record, class Close>
bool step_loop(World<D>& w, std::uint64_t& steps, More&& more, Measure&& measure, Record&& record,
               Close&& close) {
  while (more()) {
    w.measure_this_step = measure();
    step(w);
    ++steps;
    if (record()) return true;
    if (close()) return true;
  }
  return false;
}

}  // namespace geodem
