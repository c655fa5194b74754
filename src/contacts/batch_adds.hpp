// The add pass of the pair loop (contacts/batched_pairs.cpp) without a branch on the rows, for
// batches that need nothing but their forces added (no measurement, no periodic sums, no overlap
// over the limit).
//
// The scalar loop adds each contact's force and torque to grain j as it goes and keeps the row's
// own sums, which go to grain i when the next row starts. Rows of a dense 3D bed hold two or
// three touching contacts, so a branch on "the row changes here" is mispredicted about once a
// row. Here the same sums are made in the same order, in two loops:
//   contacts  each force and torque goes to grain j (or to the slab's crossings), and the row's
//             running sums are kept without a branch: at a row's first contact they restart
//             from +0 through a bit mask (0 - f, as in the scalar loop), and after each contact
//             they are written to this contact's slot;
//   rows      the slots of the rows' last contacts go to their grains i.
// The order of the additions to each grain is the scalar loop's: in a half list every partner
// j of row i is greater than i, so every contribution to grain x as a partner comes from a row
// before x's own and is added before x's row sum, in both loops, and later rows never touch x.
// The last row of the batch stays open (its sums carry over to the next batch, which may go on
// with it), as in the scalar loop.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include "contacts/contact_batch.hpp"
#include "contacts/slab_tally.hpp"
#include "world/world.hpp"

namespace geodem {

// The row whose sums carry over between batches; `row == last` (the slab's end) when no row is
// open.
template <int D>
struct OpenRowSums {
  static constexpr int kRot = ContactBatch<D>::kRot;
  std::size_t row;
  double f[D] = {};
  double t[kRot] = {};
};

// Adds the open row's sums to its grain, if a row is open, and leaves none open.
template <int D>
void close_open_row(OpenRowSums<D>& open, std::size_t last, double* force, double* torque) {
  constexpr int kRot = ContactBatch<D>::kRot;
  if (open.row == last) return;
  for (int a = 0; a < D; ++a) force[open.row * D + a] += open.f[a];
  for (int a = 0; a < kRot; ++a) torque[open.row * kRot + a] += open.t[a];
  open = OpenRowSums<D>{last};
}

template <int D>
void add_plain_batch(const ContactBatch<D>& b, int n, std::size_t last, double* __restrict force,
                     double* __restrict torque, OpenRowSums<D>& open,
                     typename SlabCrossings<SlabCrossing<D>>::Writer& crossing) {
  constexpr int kRot = ContactBatch<D>::kRot;
  if (n == 0) return;
  // The row left open by the previous batch closes first if this batch starts a new one.
  if (static_cast<std::size_t>(b.i[0]) != open.row) close_open_row(open, last, force, torque);
  alignas(64) double sum_f[D][ContactBatch<D>::kSize];
  alignas(64) double sum_t[kRot][ContactBatch<D>::kSize];
  double fi[D], ti[kRot];
  for (int a = 0; a < D; ++a) fi[a] = open.f[a];
  for (int a = 0; a < kRot; ++a) ti[a] = open.t[a];
  // No row open (open.row == last), or the batch's first row: the mask restarts the sums in
  // the first case.
  std::int64_t previous = open.row == last ? -1 : static_cast<std::int64_t>(open.row);
  for (int c = 0; c < n; ++c) {
    const std::int64_t i = b.i[c];
    const auto j = static_cast<std::size_t>(b.j[c]);
    // All ones while the row goes on, zero at its first contact: fi & 0 is +0.
    const std::uint64_t keep = std::uint64_t{0} - static_cast<std::uint64_t>(i == previous);
    previous = i;
    if (j < last) {  // same slab
      for (int a = 0; a < D; ++a) force[j * D + a] += b.f[a][c];
      for (int a = 0; a < kRot; ++a) torque[j * kRot + a] += b.tj[a][c];
    } else {
      SlabCrossing<D> x;
      for (int a = 0; a < D; ++a) x.a[a] = b.f[a][c];
      if constexpr (D == 3) {
        for (int a = 0; a < kRot; ++a) x.b[a] = b.tj[a][c];
      } else {
        x.b = b.tj[0][c];
      }
      x.body = static_cast<std::uint32_t>(j);
      crossing.push(x);
    }
    for (int a = 0; a < D; ++a) {
      fi[a] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(fi[a]) & keep) - b.f[a][c];
      sum_f[a][c] = fi[a];
    }
    for (int a = 0; a < kRot; ++a) {
      ti[a] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(ti[a]) & keep) - b.tqi[a][c];
      sum_t[a][c] = ti[a];
    }
  }
  // The rows' last contacts, packed without a branch; the batch's last row stays open.
  int ends[ContactBatch<D>::kSize];
  int m = 0;
  for (int c = 0; c + 1 < n; ++c) {
    ends[m] = c;
    m += b.i[c] != b.i[c + 1] ? 1 : 0;
  }
  for (int r = 0; r < m; ++r) {
    const int c = ends[r];
    const auto i = static_cast<std::size_t>(b.i[c]);
    for (int a = 0; a < D; ++a) force[i * D + a] += sum_f[a][c];
    for (int a = 0; a < kRot; ++a) torque[i * kRot + a] += sum_t[a][c];
  }
  open.row = static_cast<std::size_t>(b.i[n - 1]);
  for (int a = 0; a < D; ++a) open.f[a] = fi[a];
  for (int a = 0; a < kRot; ++a) open.t[a] = ti[a];
}

}  // namespace geodem
