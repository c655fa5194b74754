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
// The x and y of each force, torque and sum move as one pair of doubles (TwoDoubles: an SSE2
// register, which every x86-64 has): one load, add, mask and store for both, lane by lane the
// scalar operations, where the scalar code spent one of each per component and moved every
// masked sum through an integer register (the pass's share of a dense bed's step fell from 26
// to 22 %, docs/performance.md).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// x's bits where keep is all ones, +0 where it is zero.
inline double masked(double x, std::uint64_t keep) {
  return std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) & keep);
}

// Two doubles side by side: the x and y of a force or torque, added and masked as one SSE2
// register where the processor has SSE2 (every x86-64), as two scalars elsewhere. Each lane is
// the scalar operation on its own double, so the bits are the scalar loop's.
#if defined(__SSE2__)
struct TwoDoubles {
  __m128d v;
  static TwoDoubles load(const double* p) { return {_mm_loadu_pd(p)}; }
  static TwoDoubles of(double x, double y) { return {_mm_set_pd(y, x)}; }
  void store(double* p) const { _mm_storeu_pd(p, v); }
  // All bits kept where keep is all ones, +0 where it is zero.
  TwoDoubles masked(std::uint64_t keep) const {
    return {_mm_and_pd(v, _mm_castsi128_pd(_mm_set1_epi64x(static_cast<long long>(keep))))};
  }
  friend TwoDoubles operator+(TwoDoubles a, TwoDoubles b) { return {_mm_add_pd(a.v, b.v)}; }
  friend TwoDoubles operator-(TwoDoubles a, TwoDoubles b) { return {_mm_sub_pd(a.v, b.v)}; }
};
#else
struct TwoDoubles {
  double x, y;
  static TwoDoubles load(const double* p) { return {p[0], p[1]}; }
  static TwoDoubles of(double x, double y) { return {x, y}; }
  void store(double* p) const { p[0] = x, p[1] = y; }
  TwoDoubles masked(std::uint64_t keep) const {
    return {geodem::masked(x, keep), geodem::masked(y, keep)};
  }
  friend TwoDoubles operator+(TwoDoubles a, TwoDoubles b) { return {a.x + b.x, a.y + b.y}; }
  friend TwoDoubles operator-(TwoDoubles a, TwoDoubles b) { return {a.x - b.x, a.y - b.y}; }
};
#endif

// A grain's force (D doubles) and torque (one in 2D, three in 3D) as pairs and single doubles:
// x y of the force, then z in 3D; the torque's x y and z in 3D, its one component in 2D.
template <int D>
struct ForceAndTorque {
  // (No initializers: the add pass keeps a batch's worth of these on the stack, written before
  // they are read; the members a dimension does not use are set to zero.)
  TwoDoubles f_xy, t_xy;  // t_xy zero in 2D
  double f_z, t_z;        // f_z zero in 2D; t_z is the 2D torque

  static ForceAndTorque of_arrays(const double* f, const double* t) {
    ForceAndTorque r;
    r.f_xy = TwoDoubles::of(f[0], f[1]);
    if constexpr (D == 3) {
      r.f_z = f[2];
      r.t_xy = TwoDoubles::of(t[0], t[1]);
      r.t_z = t[2];
    } else {
      r.f_z = 0.0;
      r.t_xy = TwoDoubles::of(0.0, 0.0);
      r.t_z = t[0];
    }
    return r;
  }
  void to_arrays(double* f, double* t) const {
    f_xy.store(f);
    if constexpr (D == 3) {
      f[2] = f_z;
      t_xy.store(t);
      t[2] = t_z;
    } else {
      t[0] = t_z;
    }
  }
  // Adds this to a grain's force and torque, component by component.
  void add_to(double* f, double* t) const {
    (TwoDoubles::load(f) + f_xy).store(f);
    if constexpr (D == 3) {
      f[2] += f_z;
      (TwoDoubles::load(t) + t_xy).store(t);
      t[2] += t_z;
    } else {
      t[0] += t_z;
    }
  }
};

template <int D>
void add_plain_batch(const ContactBatch<D>& b, int n, std::size_t last, double* __restrict force,
                     double* __restrict torque, OpenRowSums<D>& open,
                     typename SlabCrossings<SlabCrossing<D>>::Writer& crossing) {
  constexpr int kRot = ContactBatch<D>::kRot;
  using Sums = ForceAndTorque<D>;
  if (n == 0) return;
  // The row left open by the previous batch closes first if this batch starts a new one.
  if (static_cast<std::size_t>(b.i[0]) != open.row) close_open_row(open, last, force, torque);
  Sums sums[ContactBatch<D>::kSize];
  Sums row = Sums::of_arrays(open.f, open.t);
  // No row open (open.row == last), or the batch's first row: the mask restarts the sums in
  // the first case.
  std::int64_t previous = open.row == last ? -1 : static_cast<std::int64_t>(open.row);
  for (int c = 0; c < n; ++c) {
    const std::int64_t i = b.i[c];
    const auto j = static_cast<std::size_t>(b.j[c]);
    // All ones while the row goes on, zero at its first contact: fi & 0 is +0.
    const std::uint64_t keep = std::uint64_t{0} - static_cast<std::uint64_t>(i == previous);
    previous = i;
    Sums on_j;  // the force on j and j's torque term
    on_j.f_xy = TwoDoubles::of(b.f[0][c], b.f[1][c]);
    if constexpr (D == 3) {
      on_j.f_z = b.f[2][c];
      on_j.t_xy = TwoDoubles::of(b.tj[0][c], b.tj[1][c]);
    } else {
      on_j.f_z = 0.0;
      on_j.t_xy = TwoDoubles::of(0.0, 0.0);
    }
    on_j.t_z = b.tj[kRot - 1][c];
    if (j < last) {  // same slab
      on_j.add_to(force + j * D, torque + j * kRot);
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
    // The row's sums: minus the force on j, minus i's torque terms.
    row.f_xy = row.f_xy.masked(keep) - on_j.f_xy;
    if constexpr (D == 3) {
      row.f_z = masked(row.f_z, keep) - on_j.f_z;
      row.t_xy = row.t_xy.masked(keep) - TwoDoubles::of(b.tqi[0][c], b.tqi[1][c]);
    }
    row.t_z = masked(row.t_z, keep) - b.tqi[kRot - 1][c];
    sums[c] = row;
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
    sums[c].add_to(force + i * D, torque + i * kRot);
  }
  open.row = static_cast<std::size_t>(b.i[n - 1]);
  row.to_arrays(open.f, open.t);
}

}  // namespace geodem
