// Verlet neighbour list with skin, in compressed rows, carrying the contact
// history (tangential spring) of every listed pair. Each pair appears once, in the
// row of its lower index. Grain-wall pairs have rows of their own.
// History is exact across rebuilds: a pair in contact is always listed (the list
// is rebuilt before any grain can move half the skin), and the rebuild merges the
// old rows into the new ones pair by pair.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "base/dim.hpp"

namespace geodem {

// Tangential spring of a contact: the friction force it exerts on body 2 (see contact_law.hpp).
// In 3D a vector in the tangent plane, turned with the plane every step. In 2D the tangent
// plane is the line of t = (-n_y, n_x): the spring is its signed component along t. That value
// turns with the normal by construction (no projection, no renormalisation) and takes half the
// memory of a 2D vector. Seen from the other body both n and t reverse, so the 2D value is the
// same from either side while the 3D vector changes sign.
template <int D>
using TangentSpring = std::conditional_t<D == 2, double, typename Dim<D>::Vec>;

template <int D>
TangentSpring<D> unloaded_spring() {
  if constexpr (D == 2) {
    return 0.0;
  } else {
    return Dim<D>::Vec::Zero();
  }
}

// The spring's own bits where keep is all ones, +0 where it is zero (a pair that parted ends its
// history without a branch on whether it did, which would mispredict as often as the touch
// test itself).
template <int D>
inline void keep_or_clear_spring(TangentSpring<D>& s, std::uint64_t keep) {
  double* p = nullptr;
  if constexpr (D == 2) {
    p = &s;
  } else {
    p = s.data();
  }
  for (int a = 0; a < (D == 2 ? 1 : D); ++a)
    p[a] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(p[a]) & keep);
}

template <int D>
double spring_norm2(const TangentSpring<D>& s) {
  if constexpr (D == 2) {
    return s * s;
  } else {
    return s.squaredNorm();
  }
}

// The spring of the same contact with the bodies' roles swapped.
template <int D>
TangentSpring<D> spring_from_other_body(const TangentSpring<D>& s) {
  if constexpr (D == 2) {
    return s;
  } else {
    return -s;
  }
}

// Contact state beyond the tangential spring, kept only when some law needs it.
template <int D>
struct ContactExtra {
  typename Dim<D>::Rot roll = Dim<D>::zero_rot();  // rolling moment spring (on body 2)
  double twist = 0.0;                              // twisting moment (3D), along n
  std::uint8_t bonded = 0;                         // cohesive bond intact
};

// In a periodic cell (world/periodic_cell.hpp): which image of a listed partner the pair is with (m
// per edge vector, -1, 0, 1).
struct CellImage {
  std::array<std::int8_t, 3> m{0, 0, 0};
  bool home() const { return m[0] == 0 && m[1] == 0 && m[2] == 0; }
};

// Resizes a list array, giving it an eighth more room when it must grow: a cleared vector
// resized past its capacity gets the exact size, and rows that grow by a few pairs a build
// would then be reallocated (fresh pages from the system) at every build.
template <typename T>
void resize_with_room(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 8 + 16);
  v.resize(n);
}

template <int D>
struct NeighbourList {
  using Spring = TangentSpring<D>;
  // Grain-grain pairs: row i is [start[i], start[i+1]) in `other` and `spring`.
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> other;
  std::vector<Spring> spring;
  // Grain-wall pairs, same layout.
  std::vector<std::uint32_t> wall_start;
  std::vector<std::uint32_t> wall;
  std::vector<Spring> wall_spring;
  // Parallel to `spring` / `wall_spring` when the world has contact extras, else empty.
  std::vector<ContactExtra<D>> extra;
  std::vector<ContactExtra<D>> wall_extra;
  // Parallel to `other` in a periodic cell, else empty.
  std::vector<CellImage> image;
  // Grain-spar element pairs (structures/), same layout; rows sorted by element.
  std::vector<std::uint32_t> spar_start;
  std::vector<std::uint32_t> spar;
  std::vector<Spring> spar_spring;

  double skin = 0.0;  // extra distance listed beyond touching (m)
  std::uint64_t builds = 0;

  std::size_t pair_count() const { return other.size(); }
  // Exchanges the rows (not the settings) with another list.
  void swap_rows(NeighbourList& o) {
    start.swap(o.start), other.swap(o.other), spring.swap(o.spring);
    wall_start.swap(o.wall_start), wall.swap(o.wall), wall_spring.swap(o.wall_spring);
    extra.swap(o.extra), wall_extra.swap(o.wall_extra), image.swap(o.image);
    spar_start.swap(o.spar_start), spar.swap(o.spar), spar_spring.swap(o.spar_spring);
  }
  // Copies the rows of another list into this one's arrays (which grow only if they must).
  void copy_rows(const NeighbourList& o) {
    start.assign(o.start.begin(), o.start.end()), other.assign(o.other.begin(), o.other.end());
    spring.assign(o.spring.begin(), o.spring.end());
    wall_start.assign(o.wall_start.begin(), o.wall_start.end());
    wall.assign(o.wall.begin(), o.wall.end());
    wall_spring.assign(o.wall_spring.begin(), o.wall_spring.end());
    extra.assign(o.extra.begin(), o.extra.end());
    wall_extra.assign(o.wall_extra.begin(), o.wall_extra.end());
    image.assign(o.image.begin(), o.image.end());
    spar_start.assign(o.spar_start.begin(), o.spar_start.end());
    spar.assign(o.spar.begin(), o.spar.end());
    spar_spring.assign(o.spar_spring.begin(), o.spar_spring.end());
  }
  std::size_t bytes() const {
    return start.capacity() * 4 + other.capacity() * 4 + spring.capacity() * sizeof(Spring) +
           wall_start.capacity() * 4 + wall.capacity() * 4 +
           wall_spring.capacity() * sizeof(Spring) +
           (extra.capacity() + wall_extra.capacity()) * sizeof(ContactExtra<D>) +
           image.capacity() * sizeof(CellImage) + spar_start.capacity() * 4 + spar.capacity() * 4 +
           spar_spring.capacity() * sizeof(Spring);
  }
};

}  // namespace geodem
