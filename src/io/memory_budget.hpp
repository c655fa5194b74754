// The memory a run will take, estimated before anything is allocated, against what the
// machine has: a run that cannot fit is refused at once (an input error naming the
// estimate) instead of ending hours later in an allocation failure.
#pragma once

#include <cstddef>
#include <string>

namespace geodem {

// Estimated peak bytes of `runs_at_once` runs side by side of `grains` grains each
// (spheres or discs; clump members count as grains): grain arrays, contact and
// neighbour lists, the placement grid of the random clouds and a checkpoint's archive,
// from peaks measured at 100,000 and 400,000 grains (about 750 B a sphere, 680 B a disc)
// with a 1.5 margin for dense packings (more contacts than a loose cloud).
double run_memory_bytes(int dimension, double grains, int runs_at_once = 1);

// What this process may use: MemAvailable (/proc/meminfo), less if the cgroup's
// memory.max is lower; GEODEM_MEMORY_LIMIT (bytes) overrides both (for tests).
double available_memory_bytes();

// Refuses a run whose estimate exceeds the available memory: an InputError naming
// `file`, the `line` and `key` of what sets the grain count, the estimate and what is
// available.
void check_memory(const std::string& file, int line, const std::string& key, int dimension,
                  double grains, int runs_at_once = 1);

// "1.23 GB"
std::string format_bytes(double bytes);

}  // namespace geodem
