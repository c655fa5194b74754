// Editing a deposited soil: excavating (removing grains and whole clumps) and holding
// part of it still while the rest is built (a trench face that stands while it is
// filled). Used by the pull-out and interface shear builders.
#pragma once

#include <cstdint>
#include <vector>

#include "world/world.hpp"

namespace geodem {

// A mask of the grains i for which pred(i) holds.
template <int D, class Pred>
std::vector<char> grains_where(const World<D>& w, Pred&& pred) {
  std::vector<char> m(w.particles.size(), 0);
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = pred(i) ? 1 : 0;
  return m;
}

// Removes every grain with remove[i] set, and whole clumps with any member removed.
// The neighbour list starts afresh. Returns the number of grains removed.
template <int D>
std::size_t remove_grains(World<D>& w, const std::vector<char>& remove) {
  auto& P = w.particles;
  auto& C = w.clumps;
  const bool clumps = !P.clump.empty();
  std::vector<char> drop_clump(C.size(), 0);
  for (std::size_t i = 0; clumps && i < P.size(); ++i)
    if (remove[i] && P.clump[i] != kNoClump) drop_clump[P.clump[i]] = 1;
  std::vector<std::uint32_t> keep, keep_clumps, clump_map(C.size(), kNoClump);
  for (std::size_t i = 0; i < P.size(); ++i) {
    const bool gone = remove[i] || (clumps && P.clump[i] != kNoClump && drop_clump[P.clump[i]]);
    if (!gone) keep.push_back(static_cast<std::uint32_t>(i));
  }
  for (std::size_t c = 0; c < C.size(); ++c)
    if (!drop_clump[c]) {
      clump_map[c] = static_cast<std::uint32_t>(keep_clumps.size());
      keep_clumps.push_back(static_cast<std::uint32_t>(c));
    }
  const std::size_t removed = P.size() - keep.size();
  P.permute(keep);
  C.permute(keep_clumps);
  for (std::size_t i = 0; clumps && i < P.size(); ++i)
    if (P.clump[i] != kNoClump) P.clump[i] = clump_map[P.clump[i]];
  NeighbourList<D> fresh;
  w.nlist.swap_rows(fresh);
  w.rebuild_needed = true;
  return removed;
}

// Holds (or releases) the bodies of the grains with select[i] set: a held grain or
// clump keeps zero velocity and does not move, though it still pushes on others.
template <int D>
void hold_grains(World<D>& w, const std::vector<char>& select, bool hold) {
  auto& P = w.particles;
  auto& C = w.clumps;
  if (hold && C.held.size() != C.size()) C.held.assign(C.size(), 0);
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (!select[i]) continue;
    if (!P.clump.empty() && P.clump[i] != kNoClump) {
      if (!C.held.empty()) C.held[P.clump[i]] = hold ? 1 : 0;
      continue;
    }
    P.flags[i] = static_cast<std::uint8_t>(hold ? (P.flags[i] | kFixed) : (P.flags[i] & ~kFixed));
  }
  for (std::size_t i = 0; i < P.size(); ++i)
    if (select[i] && hold) {
      P.vel[i].setZero();
      P.angvel[i] = Dim<D>::zero_rot();
    }
}

}  // namespace geodem
