// Editing a world between steps: removing grains and whole clumps (excavation), holding
// part of it still, adding and removing walls, changing the friction of every contact.
// Used by the lab builders (a trench face that stands while it is filled) and by the
// stages of a scene.
#pragma once

#include <cstdint>
#include <stdexcept>
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

// What becomes of the contacts of the grains that stay when others are removed.
enum class ContactHistory {
  kDiscard,  // the neighbour list starts afresh (a sample still being built)
  kKeep,     // springs, rolling springs and bonds of the remaining contacts are kept
};

// The neighbour list without the grains that left: keep[k] is the old index of new grain k
// (increasing), index_of[old] the new index or kNoClump when removed. Pairs stay in the row of
// their lower index because the renumbering keeps the order.
template <int D>
void drop_grains_from_list(NeighbourList<D>& L, const std::vector<std::uint32_t>& keep,
                           const std::vector<std::uint32_t>& index_of) {
  NeighbourList<D> out;
  // Row by row over the grains kept: entries for which kept(k) holds are copied.
  auto filter = [&keep](const std::vector<std::uint32_t>& start,
                        std::vector<std::uint32_t>& out_start, auto&& kept, auto&& copy) {
    if (start.empty()) return;
    out_start.assign(1, 0);
    std::uint32_t n = 0;
    for (const std::uint32_t old : keep) {
      for (std::uint32_t k = start[old]; k < start[old + 1]; ++k)
        if (kept(k)) copy(k), ++n;
      out_start.push_back(n);
    }
  };
  const bool extras = !L.extra.empty(), wall_extras = !L.wall_extra.empty();
  auto always = [](std::uint32_t) { return true; };
  filter(
      L.start, out.start, [&](std::uint32_t k) { return index_of[L.other[k]] != kNoClump; },
      [&](std::uint32_t k) {
        out.other.push_back(index_of[L.other[k]]), out.spring.push_back(L.spring[k]);
        if (extras) out.extra.push_back(L.extra[k]);
        if (!L.image.empty()) out.image.push_back(L.image[k]);
      });
  filter(L.wall_start, out.wall_start, always, [&](std::uint32_t k) {
    out.wall.push_back(L.wall[k]), out.wall_spring.push_back(L.wall_spring[k]);
    if (wall_extras) out.wall_extra.push_back(L.wall_extra[k]);
  });
  filter(L.spar_start, out.spar_start, always, [&](std::uint32_t k) {
    out.spar.push_back(L.spar[k]), out.spar_spring.push_back(L.spar_spring[k]);
  });
  L.swap_rows(out);
}

// Removes every grain with remove[i] set, and whole clumps with any member removed.
// Returns the number of grains removed.
template <int D>
std::size_t remove_grains(World<D>& w, const std::vector<char>& remove,
                          ContactHistory history = ContactHistory::kDiscard) {
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
  if (history == ContactHistory::kKeep) {
    std::vector<std::uint32_t> index_of(P.size(), kNoClump);
    for (std::size_t k = 0; k < keep.size(); ++k) index_of[keep[k]] = static_cast<std::uint32_t>(k);
    drop_grains_from_list(w.nlist, keep, index_of);
  } else {
    NeighbourList<D> fresh;
    w.nlist.swap_rows(fresh);
  }
  P.permute(keep);
  if (w.domain) w.domain->grains_kept(w, keep);
  C.permute(keep_clumps);
  for (std::size_t i = 0; clumps && i < P.size(); ++i)
    if (P.clump[i] != kNoClump) P.clump[i] = clump_map[P.clump[i]];
  w.collision_shares.built_for = CollisionShares::kNever;
  w.rebuild_needed = true;
  return removed;
}

// After grains were appended to the world (a stage's cloud): the neighbour list gets empty
// rows for them, so that the next build still merges the other grains' springs and bonds
// (a list whose rows do not match the grains is dropped whole by the build).
template <int D>
void add_list_rows_for_new_grains(World<D>& w, std::size_t grains_before) {
  auto& L = w.nlist;
  const std::size_t n = w.particles.size();
  for (auto* rows : {&L.start, &L.wall_start, &L.spar_start})
    if (rows->size() == grains_before + 1) rows->resize(n + 1, rows->back());
  w.rebuild_needed = true;
}

// The grain-wall pair laws for the current walls (after walls were added or removed):
// each from the grain's and the wall's materials, as World::resolve_pair_laws does.
template <int D>
void resolve_wall_laws(World<D>& w) {
  const std::size_t nm = w.materials.size(), nw = w.walls.size();
  w.wall_laws.resize(nm * nw);
  for (std::size_t a = 0; a < nm; ++a)
    for (std::size_t k = 0; k < nw; ++k) {
      PairLaw law = combine(w.materials[a], w.materials[w.walls[k].material]);
      law.per_unit_thickness = D == 2;
      w.wall_laws[a * nw + k] = law;
    }
  w.update_contact_extras();
}

// Adds a wall (its material an index of w.materials); grains find it at the next list build.
template <int D>
void add_wall(World<D>& w, const Wall<D>& wall) {
  if (wall.material >= w.materials.size()) throw std::logic_error("wall material out of range");
  // The laws already resolved for the other walls (pair-law edits included) are kept.
  const std::size_t nm = w.materials.size(), nw = w.walls.size();
  std::vector<PairLaw> old = w.wall_laws;
  w.walls.push_back(wall);
  resolve_wall_laws(w);
  for (std::size_t a = 0; a < nm && old.size() == nm * nw; ++a)
    for (std::size_t k = 0; k < nw; ++k) w.wall_laws[a * (nw + 1) + k] = old[a * nw + k];
  w.rebuild_needed = true;
}

// Removes wall `index` with its contacts and the controllers that drive it; the other walls
// keep theirs (renumbered).
template <int D>
void remove_wall(World<D>& w, std::size_t index) {
  std::erase_if(w.controllers, [index](const auto& c) { return c->wall_removed(index); });
  const std::size_t nm = w.materials.size(), nw = w.walls.size();
  auto& L = w.nlist;
  if (!L.wall_start.empty()) {
    std::size_t out = 0;
    const bool extras = !L.wall_extra.empty();
    std::uint32_t row_begin = L.wall_start[0];
    for (std::size_t i = 0; i + 1 < L.wall_start.size(); ++i) {
      const std::uint32_t row_end = L.wall_start[i + 1];
      for (std::uint32_t k = row_begin; k < row_end; ++k) {
        if (L.wall[k] == index) continue;
        L.wall[out] = L.wall[k] > index ? L.wall[k] - 1 : L.wall[k];
        L.wall_spring[out] = L.wall_spring[k];
        if (extras) L.wall_extra[out] = L.wall_extra[k];
        ++out;
      }
      row_begin = row_end;
      L.wall_start[i + 1] = static_cast<std::uint32_t>(out);
    }
    L.wall.resize(out), L.wall_spring.resize(out);
    if (extras) L.wall_extra.resize(out);
  }
  std::vector<PairLaw> laws;
  for (std::size_t a = 0; a < nm; ++a)
    for (std::size_t k = 0; k < nw; ++k)
      if (k != index) laws.push_back(w.wall_laws[a * nw + k]);
  w.walls.erase(w.walls.begin() + static_cast<std::ptrdiff_t>(index));
  w.wall_laws = std::move(laws);
}

// Sets the Coulomb friction coefficient of every grain-grain, grain-wall and grain-chain
// contact (and of the materials, for walls added later). Springs above the new limit
// slide back to it at the next step.
template <int D>
void set_friction(World<D>& w, double mu) {
  for (auto& m : w.materials) m.friction = mu;
  for (auto* table : {&w.pair_laws, &w.wall_laws})
    for (auto& law : *table) law.mu = mu;
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
