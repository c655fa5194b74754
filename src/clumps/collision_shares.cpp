#include "clumps/collision_shares.hpp"

#include <algorithm>

#include "world/world.hpp"

namespace geodem {

namespace {

// A list entry and the two bodies it joins (lo < hi for grain pairs; clump and wall for walls).
struct EntryKey {
  std::uint32_t lo, hi, entry, row;
};

// Groups the keys by (lo, hi), keeping groups of two or more entries, in a fixed order
// (lo, then hi, then entry): a counting sort on lo, then small sorts of each lo's entries.
void find_groups(std::vector<EntryKey>& keys, std::vector<EntryKey>& sorted,
                 std::vector<std::uint32_t>& bucket, std::size_t lo_count,
                 CollisionShares::Groups& groups) {
  groups.clear();
  bucket.assign(lo_count + 1, 0);
  for (const auto& k : keys) ++bucket[k.lo + 1];
  for (std::size_t b = 0; b < lo_count; ++b) bucket[b + 1] += bucket[b];
  sorted.resize(keys.size());
  for (const auto& k : keys) sorted[bucket[k.lo]++] = k;
  // bucket[b] now ends lo = b.
  std::size_t begin = 0;
  for (std::size_t b = 0; b < lo_count; ++b) {
    const std::size_t end = bucket[b];
    std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(begin),
              sorted.begin() + static_cast<std::ptrdiff_t>(end),
              [](const EntryKey& x, const EntryKey& y) {
                return x.hi != y.hi ? x.hi < y.hi : x.entry < y.entry;
              });
    for (std::size_t s = begin; s < end;) {
      std::size_t t = s + 1;
      while (t < end && sorted[t].hi == sorted[s].hi) ++t;
      if (t - s >= 2) {
        for (std::size_t u = s; u < t; ++u) {
          groups.entry.push_back(sorted[u].entry);
          groups.row.push_back(sorted[u].row);
        }
        groups.start.push_back(static_cast<std::uint32_t>(groups.entry.size()));
      }
      s = t;
    }
    begin = end;
  }
}

template <int D>
void find_all_groups(World<D>& world) {
  const auto& P = world.particles;
  const auto& L = world.nlist;
  auto& S = world.collision_shares;
  const std::uint32_t clumps = static_cast<std::uint32_t>(world.clumps.size());
  // Scratch of the build (not state); it grows once and is then reused.
  static thread_local std::vector<EntryKey> keys, sorted;
  static thread_local std::vector<std::uint32_t> bucket;
  // A body: a clump's index, or clumps + the index of a grain of no clump.
  auto body = [&](std::size_t i) {
    return P.clump[i] != kNoClump ? P.clump[i] : clumps + static_cast<std::uint32_t>(i);
  };
  keys.clear();
  for (std::size_t i = 0; i + 1 < L.start.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::uint32_t j = L.other[k];
      if (P.clump[i] == kNoClump && P.clump[j] == kNoClump) continue;
      const std::uint32_t a = body(i), b = body(j);
      keys.push_back({std::min(a, b), std::max(a, b), k, static_cast<std::uint32_t>(i)});
    }
  find_groups(keys, sorted, bucket, clumps + P.size(), S.pair_groups);
  keys.clear();
  for (std::size_t i = 0; i + 1 < L.wall_start.size(); ++i) {
    if (P.clump[i] == kNoClump) continue;
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k)
      keys.push_back({P.clump[i], L.wall[k], k, static_cast<std::uint32_t>(i)});
  }
  find_groups(keys, sorted, bucket, clumps, S.wall_groups);
  S.pair.assign(L.other.size(), 1);
  S.wall.assign(L.wall.size(), 1);
  S.built_for = L.builds;
}

// Sets every entry of each group to the number of its entries that touch now.
template <typename Touching>
void count_groups(const CollisionShares::Groups& g, std::vector<std::uint16_t>& share,
                  const Touching& touching) {
  for (std::size_t s = 0; s < g.size(); ++s) {
    std::uint32_t n = 0;
    for (std::uint32_t u = g.start[s]; u < g.start[s + 1]; ++u) n += touching(g.row[u], g.entry[u]);
    const auto k = static_cast<std::uint16_t>(std::clamp<std::uint32_t>(n, 1, 0xffff));
    for (std::uint32_t u = g.start[s]; u < g.start[s + 1]; ++u) share[g.entry[u]] = k;
  }
}

}  // namespace

template <int D>
void update_collision_shares(World<D>& world) {
  auto& S = world.collision_shares;
  if (world.clumps.size() == 0) {
    S.pair.clear(), S.wall.clear();
    S.built_for = CollisionShares::kNever;
    return;
  }
  if (S.built_for != world.nlist.builds) find_all_groups(world);
  const auto& P = world.particles;
  const auto& L = world.nlist;
  const bool extras = world.contact_extras;
  count_groups(S.pair_groups, S.pair, [&](std::uint32_t i, std::uint32_t k) {
    const std::uint32_t j = L.other[k];
    const double rs = P.radius[i] + P.radius[j];
    return world.branch(i, j, k).squaredNorm() < rs * rs || (extras && L.extra[k].bonded);
  });
  count_groups(S.wall_groups, S.wall, [&](std::uint32_t i, std::uint32_t k) {
    // As the force stage decides: a plane's signed gap, a segment's distance.
    const auto& wall = world.walls[L.wall[k]];
    const double r = P.radius[i];
    if (wall.kind == WallKind::kPlane) return (P.pos[i] - wall.point).dot(wall.normal) < r;
    typename Dim<D>::Vec q;
    if (!wall_closest(wall, P.pos[i], q)) return false;
    const double gap2 = (q - P.pos[i]).squaredNorm();
    return gap2 > 0.0 && gap2 < r * r;
  });
}

template void update_collision_shares<2>(World<2>&);
template void update_collision_shares<3>(World<3>&);

}  // namespace geodem
