// The contact history carried across a neighbour-list build: the old rows' springs, moment
// springs and bonds go to the same pairs in the new rows (src/broadphase/neighbour_search.cpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "base/parallel.hpp"
#include "contacts/neighbour_list.hpp"

namespace geodem {

// Copies the history of the pairs of an old row that are also in the new row; the
// others start from `zero`, and `dropped` sees each old entry that is not carried over.
// Both rows are sorted by partner index: one linear merge.
template <typename T, typename Dropped>
void merge_history(const std::uint32_t* old_other, const T* old_value, std::size_t old_n,
                   const std::uint32_t* new_other, T* new_value, std::size_t new_n, const T& zero,
                   Dropped&& dropped) {
  std::size_t a = 0;
  for (std::size_t b = 0; b < new_n; ++b) {
    while (a < old_n && old_other[a] < new_other[b]) dropped(old_value[a++]);
    if (a < old_n && old_other[a] == new_other[b]) {
      new_value[b] = old_value[a++];
    } else {
      new_value[b] = zero;
    }
  }
  while (a < old_n) dropped(old_value[a++]);
}

// Sorts the entries [b, e) of a row by partner, moving each spring (and moment springs and
// bond, when `extra` is given) along. Rows are short: insertion sort.
template <typename Spring, typename Extra>
void sort_row_by_partner(std::uint32_t* other, Spring* spring, Extra* extra, std::uint32_t b,
                         std::uint32_t e) {
  for (std::uint32_t x = b + 1; x < e; ++x)
    for (std::uint32_t y = x; y > b && other[y - 1] > other[y]; --y) {
      std::swap(other[y - 1], other[y]);
      std::swap(spring[y - 1], spring[y]);
      if (extra) std::swap(extra[y - 1], extra[y]);
    }
}

// Whether a value is all zero bits (+0.0 everywhere): a pair whose history is that starts
// from exactly what an unlisted pair starts from.
template <typename T>
bool zero_bits(const T& v) {
  const auto* b = reinterpret_cast<const unsigned char*>(&v);
  return std::all_of(b, b + sizeof(T), [](unsigned char c) { return c == 0; });
}

// Copies a list's rows into `old` before a build, keeping of the grain-grain rows only the
// pairs that carry a history (a tangential spring, moment springs or a bond): the merge gives
// every other pair an unloaded start, the same bits the dropped entries held. During a build
// the old rows and the new ones are both resident; the old ones then hold the touching pairs
// only, not every pair within the skin. `list` keeps its arrays: the build writes the new rows
// over them, in memory already mapped. Periodic images are not carried (see
// build_neighbour_list).
template <int D>
void keep_loaded_pairs(const NeighbourList<D>& list, NeighbourList<D>& old, std::size_t n,
                       int threads) {
  old.wall_start = list.wall_start, old.wall = list.wall, old.wall_spring = list.wall_spring;
  old.wall_extra = list.wall_extra;
  old.spar_start = list.spar_start, old.spar = list.spar, old.spar_spring = list.spar_spring;
  old.image.clear();
  old.start.clear(), old.other.clear(), old.spring.clear(), old.extra.clear();
  if (list.start.size() != n + 1) return;  // no rows of these grains: nothing to carry
  const bool extras = !list.extra.empty() && list.extra.size() == list.other.size();
  auto loaded = [&](std::size_t k) {
    if (!zero_bits(list.spring[k])) return true;
    if (!extras) return false;
    const auto& e = list.extra[k];
    return e.bonded != 0 || !zero_bits(e.roll) || !zero_bits(e.twist);
  };
  // Rows counted, then filled at their offsets, each pass on the step's threads.
  const bool par = threads > 1 && n >= kParallelMin;
  const auto rows = static_cast<std::ptrdiff_t>(n);
  auto& start = old.start;
  start.assign(n + 1, 0);
  for_each_index(rows, threads, par, [&](std::ptrdiff_t r) {
    const auto i = static_cast<std::size_t>(r);
    std::uint32_t kept = 0;
    for (std::uint32_t k = list.start[i]; k < list.start[i + 1]; ++k) kept += loaded(k) ? 1u : 0u;
    start[i + 1] = kept;
  });
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  resize_with_room(old.other, start[n]);
  resize_with_room(old.spring, start[n]);
  resize_with_room(old.extra, extras ? start[n] : 0);
  for_each_index(rows, threads, par, [&](std::ptrdiff_t r) {
    const auto i = static_cast<std::size_t>(r);
    std::uint32_t m = start[i];
    for (std::uint32_t k = list.start[i]; k < list.start[i + 1]; ++k)
      if (loaded(k)) {
        old.other[m] = list.other[k];
        old.spring[m] = list.spring[k];
        if (extras) old.extra[m] = list.extra[k];
        ++m;
      }
  });
}

}  // namespace geodem
