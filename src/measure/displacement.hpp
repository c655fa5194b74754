// Grain displacements since a reference state. Grains are renumbered as they move (cell
// order) and may be removed or added, so the reference is kept by grain id: the position of
// each id at the reference moment, NaN for an id that had no grain then.
#pragma once

#include <limits>
#include <vector>

#include "world/world.hpp"

namespace geodem {

template <int D>
std::vector<typename Dim<D>::Vec> positions_by_id(const World<D>& w) {
  const auto& P = w.particles;
  std::vector<typename Dim<D>::Vec> ref(
      P.next_id, Dim<D>::Vec::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.id[i] < ref.size()) ref[P.id[i]] = P.pos[i];
  return ref;
}

// Displacement of grain i (by index) since the reference; NaN for a grain added after it.
template <int D>
typename Dim<D>::Vec displacement(const World<D>& w, const std::vector<typename Dim<D>::Vec>& ref,
                                  std::size_t i) {
  const auto id = w.particles.id[i];
  if (id >= ref.size()) return Dim<D>::Vec::Constant(std::numeric_limits<double>::quiet_NaN());
  return w.particles.pos[i] - ref[id];
}

}  // namespace geodem
