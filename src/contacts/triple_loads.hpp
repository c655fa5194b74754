// Loads and stores of 3-vectors picked by index (grains' positions, velocities, spins; pairs'
// springs) as three vectors of components, and loads of single doubles picked by index, for
// the kernels built per instruction set (contact_batch_kernel.hpp, pair_gather_kernel.hpp; only
// files built with that set's flags include this header, and every function is a template of
// xsimd's architecture).
//
// A gather instruction loads one double a lane: three of them fetch the W vectors' components
// with 3 W loads, and on some processors (AMD Zen 4) each costs several times its W loads. Here
// each 3-vector is read by one masked load (three doubles; the masked lane is never read, so the
// last grain of an array is safe) and the W rows are transposed in registers: W loads and a few
// permutations. Bits are moved, never computed: the result is the gathers' to the bit.
#pragma once

#include <xsimd/xsimd.hpp>

#include <cstdint>
#include <type_traits>

namespace geodem::triple_detail {

// out[a] lane l = base[3 index[l] + a], a = 0, 1, 2.
template <class A>
inline void load_triples(const double* base, const std::int64_t* index,
                         xsimd::batch<double, A> (&out)[3]) {
  using V = xsimd::batch<double, A>;
  constexpr std::size_t W = V::size;
#if defined(__AVX512F__) && defined(__AVX512VL__)
  if constexpr (std::is_same_v<A, xsimd::avx512f>) {
    // Rows 2m and 2m+1 side by side in one register: x y z 0 x y z 0.
    __m512d pair[4];
    for (int m = 0; m < 4; ++m) {
      const __m512d lo = _mm512_maskz_loadu_pd(0x07, base + 3 * index[2 * m]);
      const __m256d hi = _mm256_maskz_loadu_pd(0x07, base + 3 * index[2 * m + 1]);
      pair[m] = _mm512_maskz_insertf64x4(0xff, lo, hi, 1);
    }
    const __m512i xy = _mm512_set_epi64(13, 9, 5, 1, 12, 8, 4, 0);  // x0..x3 y0..y3
    const __m512i zz = _mm512_set_epi64(14, 10, 6, 2, 14, 10, 6, 2);
    const __m512d xy_lo = _mm512_permutex2var_pd(pair[0], xy, pair[1]);
    const __m512d xy_hi = _mm512_permutex2var_pd(pair[2], xy, pair[3]);
    const __m512d z_lo = _mm512_permutex2var_pd(pair[0], zz, pair[1]);
    const __m512d z_hi = _mm512_permutex2var_pd(pair[2], zz, pair[3]);
    out[0] = _mm512_maskz_shuffle_f64x2(0xff, xy_lo, xy_hi, 0x44);
    out[1] = _mm512_maskz_shuffle_f64x2(0xff, xy_lo, xy_hi, 0xee);
    out[2] = _mm512_maskz_shuffle_f64x2(0xff, z_lo, z_hi, 0x44);
    return;
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_same_v<A, xsimd::avx2>) {
    const __m256i three = _mm256_set_epi64x(0, -1, -1, -1);
    __m256d r[4];
    for (int l = 0; l < 4; ++l) r[l] = _mm256_maskload_pd(base + 3 * index[l], three);
    const __m256d xz01 = _mm256_unpacklo_pd(r[0], r[1]), y01 = _mm256_unpackhi_pd(r[0], r[1]);
    const __m256d xz23 = _mm256_unpacklo_pd(r[2], r[3]), y23 = _mm256_unpackhi_pd(r[2], r[3]);
    out[0] = _mm256_permute2f128_pd(xz01, xz23, 0x20);
    out[1] = _mm256_permute2f128_pd(y01, y23, 0x20);
    out[2] = _mm256_permute2f128_pd(xz01, xz23, 0x31);
    return;
  }
#endif
  alignas(64) double part[3][W];
  for (std::size_t l = 0; l < W; ++l)
    for (int a = 0; a < 3; ++a) part[a][l] = base[3 * index[l] + a];
  for (int a = 0; a < 3; ++a) out[a] = V::load_aligned(part[a]);
}

// base[3 index[l] + a] = in[a] lane l for the first `live` lanes (at most W).
template <class A>
inline void store_triples(double* base, const std::int64_t* index,
                          const xsimd::batch<double, A> (&in)[3], int live) {
  using V = xsimd::batch<double, A>;
  constexpr int W = static_cast<int>(V::size);
  if (live > W) live = W;
#if defined(__AVX512F__) && defined(__AVX512VL__)
  if constexpr (std::is_same_v<A, xsimd::avx512f>) {
    const __m512d x = in[0], y = in[1], z = in[2];
    const __m512d xy_lo = _mm512_maskz_shuffle_f64x2(0xff, x, y, 0x44);  // x0..x3 y0..y3
    const __m512d xy_hi = _mm512_maskz_shuffle_f64x2(0xff, x, y, 0xee);  // x4..x7 y4..y7
    // Rows 2m and 2m+1: x y z z x y z z, z taken from the second operand (8 + lane).
    const __m512i rows[4] = {
        _mm512_set_epi64(9, 9, 5, 1, 8, 8, 4, 0), _mm512_set_epi64(11, 11, 7, 3, 10, 10, 6, 2),
        _mm512_set_epi64(13, 13, 5, 1, 12, 12, 4, 0), _mm512_set_epi64(15, 15, 7, 3, 14, 14, 6, 2)};
    for (int m = 0; m < 4 && 2 * m < live; ++m) {
      const __m512d pair = _mm512_permutex2var_pd(m < 2 ? xy_lo : xy_hi, rows[m], z);
      _mm512_mask_storeu_pd(base + 3 * index[2 * m], 0x07, pair);
      if (2 * m + 1 < live)
        _mm256_mask_storeu_pd(base + 3 * index[2 * m + 1], 0x07,
                              _mm512_maskz_extractf64x4_pd(0x0f, pair, 1));
    }
    return;
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_same_v<A, xsimd::avx2>) {
    const __m256d x = in[0], y = in[1], z = in[2];
    const __m256i three = _mm256_set_epi64x(0, -1, -1, -1);
    const __m256d xy02 = _mm256_unpacklo_pd(x, y), xy13 = _mm256_unpackhi_pd(x, y);
    const __m256d zz02 = _mm256_unpacklo_pd(z, z), zz13 = _mm256_unpackhi_pd(z, z);
    const __m256d r[4] = {
        _mm256_permute2f128_pd(xy02, zz02, 0x20), _mm256_permute2f128_pd(xy13, zz13, 0x20),
        _mm256_permute2f128_pd(xy02, zz02, 0x31), _mm256_permute2f128_pd(xy13, zz13, 0x31)};
    for (int l = 0; l < live; ++l) _mm256_maskstore_pd(base + 3 * index[l], three, r[l]);
    return;
  }
#endif
  alignas(64) double part[3][W];
  for (int a = 0; a < 3; ++a) in[a].store_aligned(part[a]);
  for (int l = 0; l < live; ++l)
    for (int a = 0; a < 3; ++a) base[3 * index[l] + a] = part[a][l];
}

// Lane l = base[index[l]]: one double a grain (the inverse masses). Loaded two lanes at a time
// (a scalar load and a load into the upper half) and the halves inserted, instead of a gather
// instruction. In the kernel this was 2 % faster on a dense bed (AMD Zen 4); in the gather
// pass, for the radii, it was slower than the gathers (docs/performance.md), which stay there.
template <class A>
inline xsimd::batch<double, A> load_singles(const double* base, const std::int64_t* index) {
  using V = xsimd::batch<double, A>;
#if defined(__AVX2__)
  auto two = [&](int l) { return _mm_loadh_pd(_mm_load_sd(base + index[l]), base + index[l + 1]); };
  auto four = [&](int l) { return _mm256_set_m128d(two(l + 2), two(l)); };
#endif
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<A, xsimd::avx512f>) {
    // (The masked forms: GCC 12's plain ones start from an undefined vector, which -Werror
    // reports as used uninitialized.)
    const __m512d low = _mm512_maskz_insertf64x4(0xff, _mm512_setzero_pd(), four(0), 0);
    return _mm512_maskz_insertf64x4(0xff, low, four(4), 1);
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_same_v<A, xsimd::avx2>) return four(0);
#endif
  alignas(64) double value[V::size];
  for (std::size_t l = 0; l < V::size; ++l) value[l] = base[index[l]];
  return V::load_aligned(value);
}

}  // namespace geodem::triple_detail
