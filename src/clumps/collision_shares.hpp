// The restitution of a collision carried by several contacts of a clump.
//
// A contact's dashpot is sized so that a collision of two bodies through that one contact
// has the restitution the user asked for: c = 2 beta sqrt(m* k), m* the two bodies' reduced
// mass. A clump that lands flat touches a wall (or another body) with k members at once:
// k such dashpots in parallel damp the one collision sqrt(k) times too much (a two-member
// clump asked for e = 0.5 rebounds with 0.37). The rule here: a collision between two bodies
// has the asked restitution however many member contacts carry it. Each of the k contacts
// that join the same two bodies at this step is damped with the mass m* / k, so that together
// they damp the collision as one contact would. A single contact (k = 1) is unchanged, and so
// is everything in a packing without clumps.
//
// The groups of list entries that join the same two bodies are found once per neighbour-list
// build (clump-clump, clump-grain, clump-wall entries); each step counts, in every group of
// two or more entries, those in contact. Spar-element contacts keep k = 1 (a sheet is not one
// rigid body).
#pragma once

#include <cstdint>
#include <vector>

namespace geodem {

struct CollisionShares {
  // Per list entry, the number of contacts that carry its collision (k above); empty when the
  // world has no clumps (k = 1 everywhere).
  std::vector<std::uint16_t> pair;  // parallel to NeighbourList::other
  std::vector<std::uint16_t> wall;  // parallel to NeighbourList::wall
  // Groups of two or more entries that join the same two bodies: group g is
  // [group_start[g], group_start[g + 1]) of entry (the list entry) and row (its grain).
  struct Groups {
    std::vector<std::uint32_t> start, entry, row;
    void clear() { start.assign(1, 0), entry.clear(), row.clear(); }
    std::size_t size() const { return start.empty() ? 0 : start.size() - 1; }
  };
  Groups pair_groups, wall_groups;
  // The list build the groups were found for (none yet: kNever). Derived data: a world read
  // back from a checkpoint finds them again.
  static constexpr std::uint64_t kNever = ~std::uint64_t{0};
  std::uint64_t built_for = kNever;
};

template <int D>
struct World;

// Brings the shares up to date for this step (groups again after a list build). No-op and
// empty shares without clumps.
template <int D>
void update_collision_shares(World<D>& world);

}  // namespace geodem
