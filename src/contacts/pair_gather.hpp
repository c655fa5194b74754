// The gather pass of the batched pair loop (contacts/batched_pairs.cpp) several listed pairs at
// a time: each vector lane measures one listed pair (distance against the sum of radii), ends
// the history of a pair apart, and the touching pairs are packed into the batch in list order.
//
// The lanes run over the slab's pairs, not row by row (a dense 3D bed lists about four pairs a
// row, half a vector): a window of pairs first gets each pair's row written beside it, one
// broadcast store a row. Each lane computes the scalar pass's operations in its order (d = x_j -
// x_i, |d|^2 = (dx^2 + dy^2) + dz^2, apart when |d|^2 >= (r_i + r_j)^2, a spring cleared when
// its own squared norm is not zero), so every instruction set keeps the same pairs and clears
// the same springs to the bit.
//
// Used where one pair law holds for the whole slab (every grain of one material), outside a
// periodic cell and without clumps' collision shares: elsewhere the scalar pass runs, which
// also changes law between batches. AVX2 (four lanes) and AVX-512 (eight), each built with its
// set's flags (pair_gather_avx2.cpp, _avx512.cpp).
#pragma once

#include <cstdint>

#include "contacts/contact_batch.hpp"

namespace geodem {

// Where the pass stands in a slab's pairs, and the rows of the current window of pairs.
struct PairWindow {
  static constexpr std::uint32_t kPairs = 256;
  std::uint32_t next = 0;    // the next pair to measure
  std::uint32_t end = 0;     // one past the slab's last pair
  std::uint32_t base = 0;    // row_of[p - base] is the row of pair p, for p in [base, filled)
  std::uint32_t filled = 0;  //
  std::uint32_t row = 0;     // the row of pair `filled`, or a row before it
  // Eight entries beyond the window: a row's broadcast store may run past it.
  alignas(64) std::uint32_t row_of[kPairs + 8] = {};
  // Starts at the first pair of row `first`; the slab's pairs end where row `last` starts.
  PairWindow(const std::uint32_t* start, std::size_t first, std::size_t last)
      : next(start[first]),
        end(start[last]),
        base(start[first]),
        filled(start[first]),
        row(static_cast<std::uint32_t>(first)) {}
};

struct PairGatherInput {
  const double* pos;     // D per grain
  const double* radius;  // one per grain
  const std::uint32_t* start;
  const std::uint32_t* other;
  double* spring;       // D components per listed pair in 3D, one in 2D
  std::uint32_t pairs;  // the list's pairs (other and spring hold this many)
};

// Whether the pass runs on a contact path (AVX2 and AVX-512).
bool pair_gather_has(ContactPath p);

// Measures listed pairs from w.next on and appends the touching ones to the batch's i, j and k
// from entry n; stops at the slab's end or when fewer than eight free entries are left. Returns
// the batch's new count.
template <int D>
int gather_touching(ContactPath p, const PairGatherInput& in, PairWindow& w, ContactBatch<D>& batch,
                    int n);

template <int D>
int gather_touching_avx2(const PairGatherInput& in, PairWindow& w, ContactBatch<D>& batch, int n);
template <int D>
int gather_touching_avx512(const PairGatherInput& in, PairWindow& w, ContactBatch<D>& batch, int n);

}  // namespace geodem
