// Verlet neighbour list with skin, in compressed rows, carrying the contact
// history (tangential spring) of every listed pair. Each pair appears once, in the
// row of its lower index. Grain-wall pairs have rows of their own.
// History is exact across rebuilds: a pair in contact is always listed (the list
// is rebuilt before any grain can move half the skin), and the rebuild merges the
// old rows into the new ones pair by pair.
#pragma once

#include <cstdint>
#include <vector>

#include "core/dim.hpp"

namespace geodem {

// Contact state beyond the tangential spring, kept only when some law needs it.
template <int D>
struct ContactExtra {
  typename Dim<D>::Rot roll = Dim<D>::zero_rot();  // rolling moment spring (on body 2)
  double twist = 0.0;                              // twisting moment (3D), along n
  std::uint8_t bonded = 0;                         // cohesive bond intact
};

template <int D>
struct NeighbourList {
  using Vec = typename Dim<D>::Vec;
  // Grain-grain pairs: row i is [start[i], start[i+1]) in `other` and `spring`.
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> other;
  std::vector<Vec> spring;
  // Grain-wall pairs, same layout.
  std::vector<std::uint32_t> wall_start;
  std::vector<std::uint32_t> wall;
  std::vector<Vec> wall_spring;
  // Parallel to `spring` / `wall_spring` when the world has contact extras, else empty.
  std::vector<ContactExtra<D>> extra;
  std::vector<ContactExtra<D>> wall_extra;
  // Grain-spar element pairs (structures/), same layout; rows sorted by element.
  std::vector<std::uint32_t> spar_start;
  std::vector<std::uint32_t> spar;
  std::vector<Vec> spar_spring;

  double skin = 0.0;  // extra distance listed beyond touching (m)
  std::uint64_t builds = 0;

  std::size_t pair_count() const { return other.size(); }
  // Exchanges the rows (not the settings) with another list.
  void swap_rows(NeighbourList& o) {
    start.swap(o.start), other.swap(o.other), spring.swap(o.spring);
    wall_start.swap(o.wall_start), wall.swap(o.wall), wall_spring.swap(o.wall_spring);
    extra.swap(o.extra), wall_extra.swap(o.wall_extra);
    spar_start.swap(o.spar_start), spar.swap(o.spar), spar_spring.swap(o.spar_spring);
  }
  std::size_t bytes() const {
    return start.capacity() * 4 + other.capacity() * 4 + spring.capacity() * sizeof(Vec) +
           wall_start.capacity() * 4 + wall.capacity() * 4 + wall_spring.capacity() * sizeof(Vec) +
           (extra.capacity() + wall_extra.capacity()) * sizeof(ContactExtra<D>) +
           spar_start.capacity() * 4 + spar.capacity() * 4 + spar_spring.capacity() * sizeof(Vec);
  }
};

}  // namespace geodem
