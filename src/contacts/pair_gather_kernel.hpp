// The vector gather pass (contacts/pair_gather.hpp) in the intrinsics of AVX2 and AVX-512. Only
// pair_gather_avx2.cpp and _avx512.cpp include this header, each built with its set's flags;
// every function here is a template of the instruction set's tag, so that no copy built for
// one set is merged with another's.
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <type_traits>

#include "contacts/pair_gather.hpp"
#include "contacts/triple_loads.hpp"

namespace geodem::pair_gather_detail {

struct Avx2 {
  static constexpr int kLanes = 4;
};
struct Avx512 {
  static constexpr int kLanes = 8;
};

// Writes the row of each pair of the next window into w.row_of: one broadcast store of eight
// rows a row (a row longer than eight, one a block of eight), each store overwritten from the
// next row's first pair on.
template <class Isa>
void fill_rows(const std::uint32_t* start, PairWindow& w) {
  const std::uint32_t base = w.next;
  const std::uint32_t end = std::min(base + PairWindow::kPairs, w.end);
  std::uint32_t r = w.row;
  for (std::uint32_t p = base; p < end;) {
    while (start[r + 1] <= p) ++r;  // the rows already done, and empty ones
    const std::uint32_t row_end = std::min(start[r + 1], end);
    const __m256i v = _mm256_set1_epi32(static_cast<int>(r));
    for (std::uint32_t q = p; q < row_end; q += 8)
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(w.row_of + (q - base)), v);
    p = row_end;
  }
  w.base = base;
  w.filled = end;
  w.row = r;
}

// Each bit of an 8-bit mask of pairs spread over the three components of the pair's spring.
struct TripleMasks {
  std::uint32_t spread[256] = {};
  constexpr TripleMasks() {
    for (std::uint32_t m = 0; m < 256; ++m)
      for (int b = 0; b < 8; ++b)
        if ((m >> b) & 1u) spread[m] |= 7u << (3 * b);
  }
};

// The springs of pairs c + l for the lanes l in `apart` whose spring has a component that is
// not zero: each ends if its squared norm (the scalar pass's test) is not zero.
template <class Isa, int S>
void end_springs(double* spring, std::uint32_t c, unsigned apart) {
  for (int l = 0; l < 8; ++l) {
    if (!((apart >> l) & 1u)) continue;
    double* s = spring + static_cast<std::size_t>(c + static_cast<std::uint32_t>(l)) * S;
    double n2 = s[0] * s[0];
    for (int a = 1; a < S; ++a) n2 += s[a] * s[a];
    if (n2 != 0.0)
      for (int a = 0; a < S; ++a) s[a] = 0.0;
  }
}

// Lanes of the pairs, among `apart`, whose spring has some component that is not +-0. The
// springs of pairs c.. lie side by side (S components each): whole vectors are loaded rather
// than gathered.
template <class Isa, int S>
unsigned springs_not_zero(const double* spring, std::uint32_t c, int lanes, unsigned apart);

#if defined(__AVX512F__)
template <>
inline unsigned springs_not_zero<Avx512, 1>(const double* spring, std::uint32_t c, int lanes,
                                            unsigned apart) {
  const auto live = static_cast<__mmask8>((1u << lanes) - 1u);
  const __m512i magnitude = _mm512_set1_epi64(0x7fffffffffffffff);
  const __m512i v = _mm512_castpd_si512(_mm512_maskz_loadu_pd(live, spring + c));
  return _mm512_mask_test_epi64_mask(static_cast<__mmask8>(apart), v, magnitude);
}

template <>
inline unsigned springs_not_zero<Avx512, 3>(const double* spring, std::uint32_t c, int lanes,
                                            unsigned apart) {
  static constexpr TripleMasks kTriple{};
  const std::uint32_t parts = (1u << (3 * lanes)) - 1u;  // the components of the live pairs
  const __m512i magnitude = _mm512_set1_epi64(0x7fffffffffffffff);
  const double* p = spring + static_cast<std::size_t>(c) * 3;
  std::uint32_t bits = 0;
  for (int v = 0; v < 3; ++v) {
    const auto load = static_cast<__mmask8>(parts >> (8 * v));
    const __m512i x = _mm512_castpd_si512(_mm512_maskz_loadu_pd(load, p + 8 * v));
    bits |= static_cast<std::uint32_t>(_mm512_test_epi64_mask(x, magnitude)) << (8 * v);
  }
  bits &= kTriple.spread[apart];
  unsigned lanes_out = 0;
  for (; bits != 0; bits &= bits - 1) lanes_out |= 1u << (std::countr_zero(bits) / 3);
  return lanes_out;
}
#endif

#if defined(__AVX2__)
template <int S>
unsigned springs_not_zero_avx2(const double* spring, std::uint32_t c, int lanes, unsigned apart) {
  static constexpr TripleMasks kTriple{};
  const __m256i magnitude = _mm256_set1_epi64x(0x7fffffffffffffff);
  const __m256i parts = _mm256_set1_epi64x(S * lanes);  // the components of the live pairs
  const double* p = spring + static_cast<std::size_t>(c) * S;
  std::uint32_t bits = 0;
  for (int v = 0; v < S; ++v) {
    const __m256i at = _mm256_set_epi64x(4 * v + 3, 4 * v + 2, 4 * v + 1, 4 * v);
    const __m256i x =
        _mm256_castpd_si256(_mm256_maskload_pd(p + 4 * v, _mm256_cmpgt_epi64(parts, at)));
    const __m256i zero = _mm256_cmpeq_epi64(_mm256_and_si256(x, magnitude), _mm256_setzero_si256());
    bits |= (~static_cast<std::uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(zero))) & 15u)
            << (4 * v);
  }
  if constexpr (S == 1) return bits & apart;
  bits &= kTriple.spread[apart];
  unsigned lanes_out = 0;
  for (; bits != 0; bits &= bits - 1) lanes_out |= 1u << (std::countr_zero(bits) / 3);
  return lanes_out;
}

template <>
inline unsigned springs_not_zero<Avx2, 1>(const double* spring, std::uint32_t c, int lanes,
                                          unsigned apart) {
  return springs_not_zero_avx2<1>(spring, c, lanes, apart);
}
template <>
inline unsigned springs_not_zero<Avx2, 3>(const double* spring, std::uint32_t c, int lanes,
                                          unsigned apart) {
  return springs_not_zero_avx2<3>(spring, c, lanes, apart);
}
#endif

// How far ahead of the pair being measured the pass asks for memory, in listed pairs.
constexpr std::uint32_t kAheadPairs = 64;

// Asks for the springs of the W listed pairs kAheadPairs after c. The pass reads every listed
// pair's spring in list order (apart pairs' springs are cleared if not zero); on a bed of a few
// hundred thousand grains the springs (24 bytes a pair, 19 MB on a settled bed of 200,000
// spheres) come from main memory, and the processor's own prefetcher, following this stream
// among the others the pass reads, did not keep up: these loads held about 45 % of the pass's
// time. Asking for the partners' state ahead as well (the grain of the group's last pair) made
// the step slower (docs/performance.md).
template <int D, int W>
inline void prefetch_springs(const PairGatherInput& in, std::uint32_t c) {
  const std::uint32_t a = c + kAheadPairs;
  if (a + W > in.pairs) return;
  constexpr int S = D == 3 ? 3 : 1;  // doubles per spring
  constexpr int kBytes = 8 * S * W;  // the W springs
  const char* spring = reinterpret_cast<const char*>(in.spring + static_cast<std::size_t>(a) * S);
  for (int at = 0; at < kBytes; at += 64) _mm_prefetch(spring + at, _MM_HINT_T0);
  _mm_prefetch(spring + (kBytes - 1), _MM_HINT_T0);
}

#if defined(__AVX512F__)
// Measures eight listed pairs from c (the `live` lanes of them); returns the touching lanes and
// ends the history of the pairs apart.
template <int D>
__mmask8 measure_avx512(const PairGatherInput& in, const PairWindow& w, std::uint32_t c,
                        __mmask8 live, __m512i& ii, __m512i& jj, __m512i& kk, __m512d (&d)[D],
                        __m512d& ri, __m512d& rj) {
  // (The gathers and widenings take a zero vector and a full mask where their plain forms
  // start from an undefined one, which GCC reports as used uninitialized.)
  const __m512d zero = _mm512_setzero_pd();
  prefetch_springs<D, 8>(in, c);
  const __m256i rows =
      _mm256_maskz_loadu_epi32(live, reinterpret_cast<const int*>(w.row_of + (c - w.base)));
  ii = _mm512_maskz_cvtepu32_epi64(0xff, rows);
  jj = _mm512_maskz_cvtepu32_epi64(0xff, _mm256_maskz_loadu_epi32(live, in.other + c));
  kk = _mm512_add_epi64(_mm512_set1_epi64(c), _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0));
  const __m512i iv =
      D == 3 ? _mm512_add_epi64(_mm512_add_epi64(ii, ii), ii) : _mm512_add_epi64(ii, ii);
  const __m512i jv =
      D == 3 ? _mm512_add_epi64(_mm512_add_epi64(jj, jj), jj) : _mm512_add_epi64(jj, jj);
  __m512d pi[D], pj[D];
  if constexpr (D == 3) {
    alignas(64) std::int64_t at_i[8], at_j[8];
    _mm512_store_si512(at_i, ii);
    _mm512_store_si512(at_j, jj);
    xsimd::batch<double, xsimd::avx512f> ti[3], tj[3];
    triple_detail::load_triples(in.pos, at_i, ti);
    triple_detail::load_triples(in.pos, at_j, tj);
    for (int a = 0; a < 3; ++a) pi[a] = ti[a], pj[a] = tj[a];
  } else {
    for (int a = 0; a < D; ++a) {
      pi[a] = _mm512_mask_i64gather_pd(zero, 0xff, iv, in.pos + a, 8);
      pj[a] = _mm512_mask_i64gather_pd(zero, 0xff, jv, in.pos + a, 8);
    }
  }
  __m512d dist2 = _mm512_setzero_pd();
  for (int a = 0; a < D; ++a) {
    d[a] = _mm512_sub_pd(pj[a], pi[a]);
    dist2 = a == 0 ? _mm512_mul_pd(d[a], d[a]) : _mm512_add_pd(dist2, _mm512_mul_pd(d[a], d[a]));
  }
  ri = _mm512_mask_i64gather_pd(zero, 0xff, ii, in.radius, 8);
  rj = _mm512_mask_i64gather_pd(zero, 0xff, jj, in.radius, 8);
  const __m512d rs = _mm512_add_pd(ri, rj);
  const __mmask8 apart = _mm512_mask_cmp_pd_mask(live, dist2, _mm512_mul_pd(rs, rs), _CMP_GE_OQ);
  // The springs of the pairs apart: those whose squared norm is not zero end.
  constexpr int S = D == 3 ? 3 : 1;
  const int lanes = std::popcount(static_cast<unsigned>(live));
  const unsigned loaded = springs_not_zero<Avx512, S>(in.spring, c, lanes, apart);
  if (loaded != 0) [[unlikely]]
    end_springs<Avx512, S>(in.spring, c, loaded);
  return static_cast<__mmask8>(live & ~apart);
}
#endif

#if defined(__AVX2__)
// The 32-bit permutation that moves the 64-bit lanes a 4-bit mask keeps to the front, in order.
struct PackOrders {
  alignas(32) std::int32_t order[16][8] = {};
  constexpr PackOrders() {
    for (int keep = 0; keep < 16; ++keep) {
      int to = 0;
      for (int pass = 0; pass < 2; ++pass)  // the kept lanes, then the others
        for (int l = 0; l < 4; ++l)
          if (((keep >> l) & 1) == (pass == 0 ? 1 : 0)) {
            order[keep][2 * to] = 2 * l;
            order[keep][2 * to + 1] = 2 * l + 1;
            ++to;
          }
    }
  }
};

inline __m256i pack_front(__m256i v, unsigned keep) {
  static constexpr PackOrders kOrders{};
  const __m256i order = _mm256_load_si256(reinterpret_cast<const __m256i*>(kOrders.order[keep]));
  return _mm256_permutevar8x32_epi32(v, order);
}

// Stores the lanes `keep` names at `to`, in order, then the others.
inline void store_front(std::int64_t* to, __m256i v, unsigned keep) {
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(to), pack_front(v, keep));
}
inline void store_front(double* to, __m256d v, unsigned keep) {
  _mm256_storeu_pd(to, _mm256_castsi256_pd(pack_front(_mm256_castpd_si256(v), keep)));
}

template <int D>
unsigned measure_avx2(const PairGatherInput& in, const PairWindow& w, std::uint32_t c, int lanes,
                      __m256i& ii, __m256i& jj, __m256i& kk, __m256d (&d)[D], __m256d& ri,
                      __m256d& rj) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  alignas(16) static constexpr std::int32_t kFirst[5][4] = {
      {0, 0, 0, 0}, {-1, 0, 0, 0}, {-1, -1, 0, 0}, {-1, -1, -1, 0}, {-1, -1, -1, -1}};
  const __m128i load = _mm_load_si128(reinterpret_cast<const __m128i*>(kFirst[lanes]));
  const unsigned live = (1u << lanes) - 1u;
  prefetch_springs<D, 4>(in, c);
  ii = _mm256_cvtepu32_epi64(
      _mm_maskload_epi32(reinterpret_cast<const int*>(w.row_of + (c - w.base)), load));
  jj = _mm256_cvtepu32_epi64(_mm_maskload_epi32(reinterpret_cast<const int*>(in.other + c), load));
  // Lanes past the window's end name pair c: the batch's entries past its count are computed
  // too, and must read springs of this slab alone (another slab's task may be writing its own).
  kk = _mm256_add_epi64(_mm256_set1_epi64x(c), _mm256_and_si256(_mm256_set_epi64x(3, 2, 1, 0),
                                                                _mm256_cvtepi32_epi64(load)));
  const __m256i iv =
      D == 3 ? _mm256_add_epi64(_mm256_add_epi64(ii, ii), ii) : _mm256_add_epi64(ii, ii);
  const __m256i jv =
      D == 3 ? _mm256_add_epi64(_mm256_add_epi64(jj, jj), jj) : _mm256_add_epi64(jj, jj);
  __m256d pi[D], pj[D];
  if constexpr (D == 3) {
    alignas(32) std::int64_t at_i[4], at_j[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(at_i), ii);
    _mm256_store_si256(reinterpret_cast<__m256i*>(at_j), jj);
    xsimd::batch<double, xsimd::avx2> ti[3], tj[3];
    triple_detail::load_triples(in.pos, at_i, ti);
    triple_detail::load_triples(in.pos, at_j, tj);
    for (int a = 0; a < 3; ++a) pi[a] = ti[a], pj[a] = tj[a];
  } else {
    for (int a = 0; a < D; ++a) {
      pi[a] = _mm256_mask_i64gather_pd(zero, in.pos + a, iv, all, 8);
      pj[a] = _mm256_mask_i64gather_pd(zero, in.pos + a, jv, all, 8);
    }
  }
  __m256d dist2 = _mm256_setzero_pd();
  for (int a = 0; a < D; ++a) {
    d[a] = _mm256_sub_pd(pj[a], pi[a]);
    dist2 = a == 0 ? _mm256_mul_pd(d[a], d[a]) : _mm256_add_pd(dist2, _mm256_mul_pd(d[a], d[a]));
  }
  ri = _mm256_mask_i64gather_pd(zero, in.radius, ii, all, 8);
  rj = _mm256_mask_i64gather_pd(zero, in.radius, jj, all, 8);
  const __m256d rs = _mm256_add_pd(ri, rj);
  const __m256d apart_v = _mm256_cmp_pd(dist2, _mm256_mul_pd(rs, rs), _CMP_GE_OQ);
  const unsigned apart = static_cast<unsigned>(_mm256_movemask_pd(apart_v)) & live;
  constexpr int S = D == 3 ? 3 : 1;
  const unsigned loaded = springs_not_zero<Avx2, S>(in.spring, c, lanes, apart);
  if (loaded != 0) [[unlikely]]
    end_springs<Avx2, S>(in.spring, c, loaded);
  return live & ~apart;
}
#endif

template <class Isa, int D>
int gather_touching(const PairGatherInput& in, PairWindow& w, ContactBatch<D>& b, int n) {
  constexpr int W = Isa::kLanes;
  while (w.next < w.end && n <= ContactBatch<D>::kSize - W) {
    if (w.next == w.filled) fill_rows<Isa>(in.start, w);
    const std::uint32_t c = w.next;
    const int lanes = static_cast<int>(std::min<std::uint32_t>(W, w.filled - c));
    if constexpr (std::is_same_v<Isa, Avx512>) {
#if defined(__AVX512F__)
      const auto live = static_cast<__mmask8>((1u << lanes) - 1u);
      __m512i ii, jj, kk;
      __m512d d[D];
      __m512d ri, rj;
      const __mmask8 keep = measure_avx512<D>(in, w, c, live, ii, jj, kk, d, ri, rj);
      _mm512_storeu_si512(b.i + n, _mm512_maskz_compress_epi64(keep, ii));
      _mm512_storeu_si512(b.j + n, _mm512_maskz_compress_epi64(keep, jj));
      // The lanes after the kept ones: pair c (of this window) rather than zeros, so that a
      // kernel's loads beyond the batch's end read this slab's springs, never pair 0's, which
      // the first slab's task may be writing (indices i and j of grains are only read).
      _mm512_storeu_si512(b.k + n, _mm512_mask_compress_epi64(_mm512_set1_epi64(c), keep, kk));
      for (int a = 0; a < D; ++a)
        _mm512_storeu_pd(b.d[a] + n, _mm512_maskz_compress_pd(keep, d[a]));
      _mm512_storeu_pd(b.radius_i + n, _mm512_maskz_compress_pd(keep, ri));
      _mm512_storeu_pd(b.radius_j + n, _mm512_maskz_compress_pd(keep, rj));
      n += std::popcount(static_cast<unsigned>(keep));
#endif
    } else {
#if defined(__AVX2__)
      __m256i ii, jj, kk;
      __m256d d[D];
      __m256d ri, rj;
      const unsigned keep = measure_avx2<D>(in, w, c, lanes, ii, jj, kk, d, ri, rj);
      store_front(b.i + n, ii, keep);
      store_front(b.j + n, jj, keep);
      store_front(b.k + n, kk, keep);
      for (int a = 0; a < D; ++a) store_front(b.d[a] + n, d[a], keep);
      store_front(b.radius_i + n, ri, keep);
      store_front(b.radius_j + n, rj, keep);
      n += std::popcount(keep);
#endif
    }
    w.next = c + static_cast<std::uint32_t>(lanes);
  }
  return n;
}

}  // namespace geodem::pair_gather_detail

#define GEODEM_PAIR_GATHER(NAME, ISA)                                                           \
  namespace geodem {                                                                            \
  template <int D>                                                                              \
  int gather_touching_##NAME(const PairGatherInput& in, PairWindow& w, ContactBatch<D>& batch,  \
                             int n) {                                                           \
    return pair_gather_detail::gather_touching<pair_gather_detail::ISA, D>(in, w, batch, n);    \
  }                                                                                             \
  template int gather_touching_##NAME<2>(const PairGatherInput&, PairWindow&, ContactBatch<2>&, \
                                         int);                                                  \
  template int gather_touching_##NAME<3>(const PairGatherInput&, PairWindow&, ContactBatch<3>&, \
                                         int);                                                  \
  }
