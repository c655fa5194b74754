// The batch kernel, written once over xsimd's vectors and built for each instruction set by
// its own file (contact_batch_sse2.cpp, _avx2.cpp, _avx512.cpp, each with that set's compiler
// flags). Only those files include this header: code built for AVX-512 must not be merged
// with the baseline copy of an inline function, so the kernel calls nothing but xsimd's
// functions of its own instruction set and reads the law from BatchLaw's plain fields.
//
// Each lane runs the operations of the scalar law (contacts/contact_law.hpp) in the same order:
// what the scalar code decides by a branch (the spring's turn into the tangent plane, Coulomb's
// limit, the dashpot) is computed in every lane and selected, so that the chosen values are
// the scalar ones to the bit. Products and sums are never fused (-ffp-contract=off).
#pragma once

#include <xsimd/xsimd.hpp>

#include <cstdint>
#include <type_traits>

#include "contacts/contact_batch.hpp"
#include "contacts/triple_loads.hpp"

namespace geodem::batch_kernel_detail {

// base[index] lane by lane, with the processor's gather instruction where it has one (xsimd
// 8.1's own gather of doubles falls back to one load per lane).
template <class A>
inline xsimd::batch<double, A> gather(const double* base,
                                      const xsimd::batch<std::int64_t, A>& index) {
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<A, xsimd::avx512f>) {
    return _mm512_i64gather_pd(index, base, sizeof(double));
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_same_v<A, xsimd::avx2>) {
    return _mm256_i64gather_pd(base, index, sizeof(double));
  }
#endif
  constexpr std::size_t W = xsimd::batch<double, A>::size;
  alignas(64) std::int64_t at[W];
  alignas(64) double value[W];
  index.store_aligned(at);
  for (std::size_t l = 0; l < W; ++l) value[l] = base[at[l]];
  return xsimd::batch<double, A>::load_aligned(value);
}

// Writes the springs (`parts` components each) of a vector's contacts back to the list: all
// lanes at once when the vector is full (AVX-512 has a scatter instruction), else only the
// `live` lanes that hold contacts.
template <int W, class V, class I>
inline void store_springs(const V* s, double* spring, const I& index, int parts, int live) {
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<typename V::arch_type, xsimd::avx512f>) {
    if (live >= W) {
      for (int a = 0; a < parts; ++a) _mm512_i64scatter_pd(spring + a, index, s[a], sizeof(double));
      return;
    }
  }
#endif
  if (live > W) live = W;
  alignas(64) double value[W];
  alignas(64) std::int64_t at[W];
  index.store_aligned(at);
  for (int a = 0; a < parts; ++a) {
    s[a].store_aligned(value);
    for (int l = 0; l < live; ++l) spring[at[l] + a] = value[l];
  }
}

template <class A, int D, bool Periodic, bool Hertz>
inline void kernel(const BatchLaw& law, const BatchGrains& g, double dt, ContactBatch<D>& b,
                   int n) {
  using V = xsimd::batch<double, A>;
  using I = xsimd::batch<std::int64_t, A>;
  constexpr int W = static_cast<int>(V::size);
  constexpr int R = ContactBatch<D>::kRot;
  static_assert(ContactBatch<D>::kSize % 8 == 0 && W <= 8);
  const V zero(0.0), one(1.0), half(0.5), two(2.0);
  const V kn_c(law.kn), kt_c(law.kt), e1r(law.e1r), e2r(law.e2r), kt_over_kn(law.kt_over_kn);
  const V mu(law.mu), beta(law.beta), hertz_damp(law.hertz_damp), estar(law.estar);
  const V gstar(law.gstar), vdt(dt);
  const V four_thirds_estar = V(4.0 / 3.0) * estar, eight_gstar = V(8.0) * gstar;
  const V two_estar = two * estar, two_beta = two * beta;
  const V overlap_limit(b.overlap_limit);
  alignas(64) static constexpr double kLane[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  const V lane = V::load_aligned(kLane);
  auto overlapping = xsimd::batch_bool<double, A>(false);
  auto load = [](const double* p) { return V::load_aligned(p); };
  // Component a of D-vector (or spin) number `index` of an array of them.
  auto gather_part = [](const double* base, const I& index, int a) {
    return gather<A>(base + a, index);
  };
  const bool measured = !Periodic && b.measured;  // d and the radii read, not loaded again
  for (int c = 0; c < n; c += W) {
    const I ii = I::load_aligned(b.i + c), jj = I::load_aligned(b.j + c);
    const I kk = I::load_aligned(b.k + c);
    const I iv = D == 3 ? ii + ii + ii : ii + ii, jv = D == 3 ? jj + jj + jj : jj + jj;
    const I ir = R == 3 ? ii + ii + ii : ii, jr = R == 3 ? jj + jj + jj : jj;
    const I ks = D == 3 ? kk + kk + kk : kk;
    auto singles = [&](const double* base, const std::int64_t* index) {
      return triple_detail::load_singles<A>(base, index + c);
    };
    const V ri = measured ? load(b.radius_i + c) : singles(g.radius, b.i);
    const V rj = measured ? load(b.radius_j + c) : singles(g.radius, b.j);
    V inv_msum = singles(g.inv_mass, b.i) + singles(g.inv_mass, b.j);
    if (g.shares) inv_msum = inv_msum * load(b.share + c);
    // In 3D each grain's (or spring's) three components are loaded together and transposed
    // (contacts/triple_loads.hpp); in 2D they are gathered.
    auto parts = [&](const double* base, const std::int64_t* index, const I& scaled, V* out,
                     int count) {
      if constexpr (D == 3) {
        if (count == 3) {
          V three[3];
          triple_detail::load_triples<A>(base, index, three);
          for (int a = 0; a < 3; ++a) out[a] = three[a];
          return;
        }
      }
      for (int a = 0; a < count; ++a) out[a] = gather_part(base, scaled, a);
    };
    V dv[D];
    if (Periodic || measured) {
      for (int a = 0; a < D; ++a) dv[a] = load(b.d[a] + c);
    } else {
      V pi[D], pj[D];
      parts(g.pos, b.i + c, iv, pi, D);
      parts(g.pos, b.j + c, jv, pj, D);
      for (int a = 0; a < D; ++a) {
        dv[a] = pj[a] - pi[a];
        dv[a].store_aligned(b.d[a] + c);
      }
    }
    V dist2 = dv[0] * dv[0] + dv[1] * dv[1];
    if constexpr (D == 3) dist2 += dv[2] * dv[2];
    const V dist = xsimd::sqrt(dist2);
    const V inv_dist = one / dist;
    V nv[D];
    for (int a = 0; a < D; ++a) nv[a] = dv[a] * inv_dist;
    const V delta = (ri + rj) - dist;
    const V ai = ri - half * delta, aj = rj - half * delta;
    V vi[D], vj[D], wi[R], wj[R];
    parts(g.vel, b.i + c, iv, vi, D);
    parts(g.vel, b.j + c, jv, vj, D);
    parts(g.angvel, b.i + c, ir, wi, R);
    parts(g.angvel, b.j + c, jr, wj, R);
    // Relative velocity of the surfaces: (v_j - w_j x (aj n)) - (v_i + w_i x (ai n)).
    V vr[D];
    if constexpr (D == 3) {
      const V jx = aj * nv[0], jy = aj * nv[1], jz = aj * nv[2];
      const V ix = ai * nv[0], iy = ai * nv[1], iz = ai * nv[2];
      vr[0] = (vj[0] - (wj[1] * jz - wj[2] * jy)) - (vi[0] + (wi[1] * iz - wi[2] * iy));
      vr[1] = (vj[1] - (wj[2] * jx - wj[0] * jz)) - (vi[1] + (wi[2] * ix - wi[0] * iz));
      vr[2] = (vj[2] - (wj[0] * jy - wj[1] * jx)) - (vi[2] + (wi[0] * iy - wi[1] * ix));
    } else {
      vr[0] = (vj[0] - (-wj[0]) * (aj * nv[1])) - (vi[0] + (-wi[0]) * (ai * nv[1]));
      vr[1] = (vj[1] - wj[0] * (aj * nv[0])) - (vi[1] + wi[0] * (ai * nv[0]));
    }
    if constexpr (Periodic) {
      for (int a = 0; a < D; ++a) vr[a] += load(b.vel_shift[a] + c);
    }
    V vn = vr[0] * nv[0] + vr[1] * nv[1];
    if constexpr (D == 3) vn += vr[2] * nv[2];
    // The normal force, the tangential stiffness and the dashpot (LinearLaw, HertzLaw).
    V fn, kt, cn;
    const auto damped_mass = inv_msum > zero;
    if constexpr (Hertz) {
      const V a = xsimd::sqrt(ri * rj / (ri + rj) * delta);
      cn = xsimd::select((hertz_damp > zero) & damped_mass,
                         hertz_damp * xsimd::sqrt(two_estar * a / inv_msum), zero);
      fn = four_thirds_estar * a * delta - cn * vn;
      kt = eight_gstar * a;
    } else {
      V kn = kn_c;
      if (!law.constant_stiffness) {
        const V ea = e1r * ri, eb = e2r * rj;
        const V k = two * ea * eb / (ea + eb);
        kn = law.per_unit_thickness ? k / (half * (ri + rj)) : k;
      }
      cn = xsimd::select((beta > zero) & damped_mass, two_beta * xsimd::sqrt(kn / inv_msum), zero);
      fn = kn * delta - cn * vn;
      kt = law.constant_stiffness ? kt_c : kt_over_kn * kn;
    }
    const V limit = mu * xsimd::select(fn < zero, zero, fn);
    const V kt_dt = kt * vdt;
    V f[D];
    if constexpr (D == 3) {
      V s[3];
      triple_detail::load_triples<A>(g.spring, b.k + c, s);
      // The spring turned into the new tangent plane (keep_in_tangent_plane).
      const V s2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
      const V sn = s[0] * nv[0] + s[1] * nv[1] + s[2] * nv[2];
      const V x = sn * sn / s2;
      // The series where the normal turned little (x < 1e-5), else 1 / sqrt(1 - x) (rare: the
      // root is paid only when a lane needs it), and no scaling from x = 1 on.
      const auto tiny = x < V(1e-5), turned = (~tiny) & (x < one);
      V scale = one + x * (half + V(0.375) * x);
      if (xsimd::any(turned)) [[unlikely]]
        scale = xsimd::select(turned, one / xsimd::sqrt(one - x), scale);
      scale = xsimd::select(tiny | turned, scale, one);
      const auto loaded = s2 > zero;
      for (int a = 0; a < 3; ++a) s[a] = xsimd::select(loaded, (s[a] - sn * nv[a]) * scale, s[a]);
      V vt[3], ft[3];
      for (int a = 0; a < 3; ++a) vt[a] = vr[a] - vn * nv[a];
      for (int a = 0; a < 3; ++a) s[a] = s[a] - kt_dt * vt[a];
      // Coulomb's limit on the spring, or on spring plus dashpot (which the spring then takes).
      for (int a = 0; a < 3; ++a) ft[a] = law.tangential_damping ? s[a] - cn * vt[a] : s[a];
      const V ft2 = ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2];
      const auto slips = ~(ft2 <= limit * limit);
      if (xsimd::any(slips)) {
        const V shrink = limit / xsimd::sqrt(ft2);
        for (int a = 0; a < 3; ++a) {
          ft[a] = xsimd::select(slips, ft[a] * shrink, ft[a]);
          s[a] = xsimd::select(slips, ft[a], s[a]);
        }
      }
      triple_detail::store_triples<A>(g.spring, b.k + c, s, n - c);
      for (int a = 0; a < 3; ++a) f[a] = fn * nv[a] + ft[a];
      const V tq[3] = {nv[1] * f[2] - nv[2] * f[1], nv[2] * f[0] - nv[0] * f[2],
                       nv[0] * f[1] - nv[1] * f[0]};
      for (int a = 0; a < 3; ++a) {
        (ai * tq[a]).store_aligned(b.tqi[a] + c);
        (-(aj * tq[a])).store_aligned(b.tj[a] + c);
      }
    } else {
      V s = gather_part(g.spring, ks, 0);
      const V vt = nv[0] * vr[1] - nv[1] * vr[0];
      s = s - kt_dt * vt;
      V ft = law.tangential_damping ? s - cn * vt : s;
      const auto slips = ~(xsimd::abs(ft) <= limit);
      ft = xsimd::select(slips, xsimd::copysign(limit, ft), ft);
      s = xsimd::select(slips, ft, s);
      store_springs<W>(&s, g.spring, ks, 1, n - c);
      f[0] = fn * nv[0] + (-ft) * nv[1];
      f[1] = fn * nv[1] + ft * nv[0];
      const V tq = nv[0] * f[1] - nv[1] * f[0];
      (ai * tq).store_aligned(b.tqi[0] + c);
      (-(aj * tq)).store_aligned(b.tj[0] + c);
    }
    for (int a = 0; a < D; ++a) f[a].store_aligned(b.f[a] + c);
    fn.store_aligned(b.fn + c);
    delta.store_aligned(b.delta + c);
    const auto live = lane < V(static_cast<double>(n - c));
    overlapping = overlapping | (live & (delta > overlap_limit * xsimd::select(rj < ri, rj, ri)));
  }
  b.overlap_seen = xsimd::any(overlapping);
}

template <class A, int D, bool Periodic>
void run(const BatchLaw& law, const BatchGrains& g, double dt, ContactBatch<D>& b, int n) {
  if (law.hertz) {
    kernel<A, D, Periodic, true>(law, g, dt, b, n);
  } else {
    kernel<A, D, Periodic, false>(law, g, dt, b, n);
  }
}

}  // namespace geodem::batch_kernel_detail

// Defines batch_kernel_<NAME><D, Periodic> for xsimd's architecture ARCH.
#define GEODEM_BATCH_KERNELS(NAME, ARCH)                                                   \
  namespace geodem {                                                                       \
  template <int D, bool Periodic>                                                          \
  void batch_kernel_##NAME(const BatchLaw& law, const BatchGrains& g, double dt,           \
                           ContactBatch<D>& b, int n) {                                    \
    batch_kernel_detail::run<ARCH, D, Periodic>(law, g, dt, b, n);                         \
  }                                                                                        \
  template void batch_kernel_##NAME<2, false>(const BatchLaw&, const BatchGrains&, double, \
                                              ContactBatch<2>&, int);                      \
  template void batch_kernel_##NAME<2, true>(const BatchLaw&, const BatchGrains&, double,  \
                                             ContactBatch<2>&, int);                       \
  template void batch_kernel_##NAME<3, false>(const BatchLaw&, const BatchGrains&, double, \
                                              ContactBatch<3>&, int);                      \
  template void batch_kernel_##NAME<3, true>(const BatchLaw&, const BatchGrains&, double,  \
                                             ContactBatch<3>&, int);                       \
  }
