// The move kernel (integrate/move_kernel.hpp) written once over xsimd's vectors; only the files
// that build it for one instruction set include this header (as for the contact kernel, code
// built with AVX-512 flags must not share an inline function with the baseline build).
#pragma once

#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "integrate/move_kernel.hpp"

namespace geodem::move_kernel_detail {

// Lane l of vector E of a block's components (D per grain) belongs to grain (E W + l) / D.
template <int E, int D>
struct GrainOfComponent {
  static constexpr std::uint64_t get(unsigned l, unsigned w) { return (E * w + l) / D; }
};

// A block of W grains' per-grain values `one` spread over its N = D W components (one vector per
// E).
template <class A, int D, std::size_t... E>
inline void spread(const xsimd::batch<double, A>& one, xsimd::batch<double, A>* out,
                   std::index_sequence<E...>) {
  using U = xsimd::batch<std::uint64_t, A>;
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<A, xsimd::avx512f>) {
    // The permutation with every lane selected: xsimd's swizzle starts from an undefined vector,
    // which GCC 12 reports as used uninitialized at -O1 (a false alarm in its own header).
    ((out[E] = _mm512_mask_permutexvar_pd(
          one, 0xFF, U(xsimd::make_batch_constant<U, GrainOfComponent<E, D>>()), one)),
     ...);
    return;
  }
#endif
  ((out[E] = xsimd::swizzle(one, xsimd::make_batch_constant<U, GrainOfComponent<E, D>>())), ...);
}

// v <- v + a dt and x <- x + v dt on one block's N vectors of components, a = F inv (+ g);
// `accel` and `moved` select per component where the block holds grains that are fixed or
// left alone (null: every grain accelerates and moves); `x` is null for spins.
template <class A, int N, bool Damped>
inline void advance(const double* force, const xsimd::batch<double, A>* inv,
                    const xsimd::batch<double, A>* g, const double* accel, const double* moved,
                    double* vel, double* x, double* speed2, double dt, double alpha) {
  using V = xsimd::batch<double, A>;
  constexpr int W = static_cast<int>(V::size);
  const V vdt(dt), valpha(alpha), half_dt(0.5 * dt), zero(0.0);
  for (int e = 0; e < N; ++e) {
    V v = V::load_unaligned(vel + e * W);
    V acc = V::load_unaligned(force + e * W) * inv[e];
    if (g != nullptr) acc = acc + g[e];
    if constexpr (Damped) acc = acc - xsimd::copysign(valpha * xsimd::abs(acc), v + half_dt * acc);
    v = accel == nullptr ? v + acc * vdt
                         : xsimd::select(V::load_aligned(accel + e * W) != zero, v + acc * vdt, v);
    v.store_unaligned(vel + e * W);
    if (x != nullptr) {
      const V pos = V::load_unaligned(x + e * W);
      const V next = pos + v * vdt;
      (moved == nullptr ? next : xsimd::select(V::load_aligned(moved + e * W) != zero, next, pos))
          .store_unaligned(x + e * W);
      (v * v).store_aligned(speed2 + e * W);
    }
  }
}

template <class A, int D, bool Damped>
double move(const MoveConstants& c, const MoveArrays& m, std::size_t first, std::size_t last) {
  using V = xsimd::batch<double, A>;
  constexpr int R = D == 3 ? 3 : 1;
  constexpr int G = static_cast<int>(V::size);  // grains per block
  static_assert(kMoveBlock % G == 0);
  V gravity[D];
  {
    alignas(64) double g[D * G];
    for (int e = 0; e < D * G; ++e) g[e] = c.gravity[e % D];
    for (int e = 0; e < D; ++e) gravity[e] = V::load_aligned(g + e * G);
  }
  alignas(64) double accel[D * G], moved[D * G], speed2[D * G], spin_accel[R * G];
  const std::uint8_t special = c.left_alone | c.fixed;
  double vmax2 = 0.0;
  for (std::size_t b = first; b < last; b += G) {
    std::uint8_t seen = 0;
    for (int q = 0; q < G; ++q) seen |= m.flags[b + q];
    const bool plain = (seen & special) == 0;  // every grain accelerates and moves
    if (!plain) {
      for (int q = 0; q < G; ++q) {
        const std::uint8_t f = m.flags[b + q];
        const bool left = (f & c.left_alone) != 0, acc = !left && !(f & c.fixed);
        for (int k = 0; k < D; ++k) {
          accel[q * D + k] = acc ? 1.0 : 0.0;
          moved[q * D + k] = left ? 0.0 : 1.0;
        }
        for (int k = 0; k < R; ++k) spin_accel[q * R + k] = acc ? 1.0 : 0.0;
      }
    }
    V inv[D];
    spread<A, D>(V::load_unaligned(m.inv_mass + b), inv, std::make_index_sequence<D>());
    advance<A, D, Damped>(m.force + b * D, inv, gravity, plain ? nullptr : accel,
                          plain ? nullptr : moved, m.vel + b * D, m.pos + b * D, speed2, c.dt,
                          c.alpha);
    V inv_spin[R];
    spread<A, R>(V::load_unaligned(m.inv_inertia + b), inv_spin, std::make_index_sequence<R>());
    advance<A, R, Damped>(m.torque + b * R, inv_spin, nullptr, plain ? nullptr : spin_accel,
                          nullptr, m.angvel + b * R, nullptr, nullptr, c.dt, c.alpha);
    for (int q = 0; q < G; ++q) {
      if (!plain && moved[q * D] == 0.0) continue;
      // Eigen's squaredNorm: (x^2 + y^2) + z^2.
      double s = speed2[q * D] + speed2[q * D + 1];
      if constexpr (D == 3) s += speed2[q * D + 2];
      vmax2 = std::max(vmax2, s);
    }
  }
  return vmax2;
}

template <class A, int D>
double run(const MoveConstants& c, const MoveArrays& m, std::size_t first, std::size_t last) {
  return c.alpha > 0.0 ? move<A, D, true>(c, m, first, last) : move<A, D, false>(c, m, first, last);
}

}  // namespace geodem::move_kernel_detail

// Defines move_kernel_<NAME><D> for xsimd's architecture ARCH.
#define GEODEM_MOVE_KERNELS(NAME, ARCH)                                                       \
  namespace geodem {                                                                          \
  template <int D>                                                                            \
  double move_kernel_##NAME(const MoveConstants& c, const MoveArrays& m, std::size_t first,   \
                            std::size_t last) {                                               \
    return move_kernel_detail::run<ARCH, D>(c, m, first, last);                               \
  }                                                                                           \
  template double move_kernel_##NAME<2>(const MoveConstants&, const MoveArrays&, std::size_t, \
                                        std::size_t);                                         \
  template double move_kernel_##NAME<3>(const MoveConstants&, const MoveArrays&, std::size_t, \
                                        std::size_t);                                         \
  }
