// Grains given one by one (particles, particle files, Python's add_grains) that overlap by
// more than the step stops at are an input error naming both, not an instability at step 0.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "particles/random_cloud.hpp"

namespace geodem {

// Throws InputError (scenario `scenario`) at the first grain that overlaps an earlier one by
// more than `limit` x the smaller radius, naming both with `name` (called for the error only:
// no text is kept per grain). A counting-sorted cell grid of the largest diameter: O(N), about
// 16 bytes a grain, where a hash map of cells took some 100 and left its holes in the heap.
template <int D>
void reject_input_overlaps(const std::vector<Sphere<D>>& g,
                           const std::function<std::string(std::size_t)>& name, double limit,
                           const std::string& scenario);

}  // namespace geodem
