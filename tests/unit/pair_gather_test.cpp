// The vector gather pass (contacts/pair_gather.hpp) keeps exactly the pairs the scalar pass
// keeps, in list order, with the branch and radii the kernel then reads, and ends exactly the
// springs it ends, on every path the machine runs.
// The list is built by hand to reach its corners: empty rows, rows of one pair and rows longer
// than a vector and than a window of pairs, slabs that start and end inside the list, pairs
// just touching or just apart (at 1 ulp), and springs of every kind on pairs apart: zero, -0,
// loaded, a NaN, and a tiny one whose squared norm is zero (the scalar test keeps it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <random>
#include <utility>
#include <vector>

#include "contacts/neighbour_list.hpp"
#include "contacts/pair_gather.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class PairGather : public ::testing::Test {};
TYPED_TEST_SUITE(PairGather, Dims, DimNames);

template <int D>
struct HandList {
  std::vector<Vec<D>> pos;
  std::vector<double> radius;
  std::vector<std::uint32_t> start{0};
  std::vector<std::uint32_t> other;
  std::vector<TangentSpring<D>> spring;
};

template <int D>
TangentSpring<D> spring_of_kind(int kind, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto all = [](double v) {
    if constexpr (D == 2) {
      return v;
    } else {
      return Vec<3>(v, v, v);
    }
  };
  switch (kind) {
    case 0:
      return all(0.0);
    case 1:
      return all(-0.0);
    case 2:
      return all(1e-170);  // its squared norm underflows to zero: kept
    case 3:
      return all(std::nan(""));
    default:
      if constexpr (D == 2) {
        return u(rng);
      } else {
        return Vec<3>(u(rng), 0.0, u(rng));
      }
  }
}

// Grains on a line 1 apart with radii near 0.5, so that each listed pair is touching or apart
// by a random margin, sometimes by one ulp either side of the sum of radii.
template <int D>
HandList<D> hand_list(std::size_t grains, std::uint64_t seed) {
  HandList<D> h;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < grains; ++i) {
    Vec<D> x = Vec<D>::Zero();
    x[0] = static_cast<double>(i);
    x[1] = 0.3 * u(rng);
    h.pos.push_back(x);
    h.radius.push_back(0.45 + 0.1 * u(rng));
  }
  const int lengths[] = {0, 1, 3, 0, 9, 17, 2, 300, 5, 4, 0, 8, 7};
  for (std::size_t i = 0; i < grains; ++i) {
    const int len = lengths[i % std::size(lengths)];
    for (int m = 0; m < len; ++m) {
      std::uint32_t j = static_cast<std::uint32_t>(u(rng) * static_cast<double>(grains));
      if (m % 5 == 0) j = static_cast<std::uint32_t>((i + 1) % grains);  // often touching
      if (m % 11 == 3) {
        // The next grain exactly at the sum of radii or one ulp inside: the test's two sides.
        j = static_cast<std::uint32_t>((i + 1) % grains);
        const double d = std::sqrt((h.pos[j] - h.pos[i]).squaredNorm());
        h.radius[j] = m % 2 ? d - h.radius[i] : std::nextafter(d - h.radius[i], 0.0);
      }
      h.other.push_back(j);
      h.spring.push_back(spring_of_kind<D>(static_cast<int>(u(rng) * 6.0), rng));
    }
    h.start.push_back(static_cast<std::uint32_t>(h.other.size()));
  }
  return h;
}

struct Kept {
  std::vector<std::int64_t> i, j, k;
  std::vector<double> d, ri, rj;  // per kept pair: x_j - x_i (D components), the radii
  int foreign = 0;                // pairs of another slab named past a batch's count (vector pass)
};

// The scalar pass's decisions (contacts/batched_pairs.cpp).
template <int D>
Kept scalar_pass(HandList<D>& h, std::size_t first, std::size_t last) {
  Kept kept;
  for (std::size_t i = first; i < last; ++i) {
    for (std::uint32_t k = h.start[i]; k < h.start[i + 1]; ++k) {
      const std::uint32_t j = h.other[k];
      const Vec<D> d = h.pos[j] - h.pos[i];
      const double rs = h.radius[i] + h.radius[j];
      const bool apart = d.squaredNorm() >= rs * rs;
      const bool ends = apart & (spring_norm2<D>(h.spring[k]) != 0.0);
      keep_or_clear_spring<D>(h.spring[k], std::uint64_t{0} - static_cast<std::uint64_t>(!ends));
      if (!apart) {
        kept.i.push_back(static_cast<std::int64_t>(i));
        kept.j.push_back(j);
        kept.k.push_back(k);
        for (int a = 0; a < D; ++a) kept.d.push_back(d[a]);
        kept.ri.push_back(h.radius[i]);
        kept.rj.push_back(h.radius[j]);
      }
    }
  }
  return kept;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  // (memcmp must not see the null data of an empty vector.)
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

template <int D>
Kept vector_pass(ContactPath path, HandList<D>& h, std::size_t first, std::size_t last) {
  Kept kept;
  const PairGatherInput in{h.pos.front().data(),
                           h.radius.data(),
                           h.start.data(),
                           h.other.data(),
                           reinterpret_cast<double*>(h.spring.data()),
                           static_cast<std::uint32_t>(h.other.size())};
  PairWindow w(h.start.data(), first, last);
  ContactBatch<D> batch{};
  std::fill(std::begin(batch.k), std::end(batch.k), static_cast<std::int64_t>(h.start[first]));
  int n = 0;
  auto flush = [&] {
    // The lanes a kernel computes past the count (up to a whole vector of 8) must name pairs of
    // this slab: another slab's task may be writing its own pairs' springs meanwhile.
    for (int c = n; c < std::min<int>(ContactBatch<D>::kSize, (n + 7) / 8 * 8); ++c)
      if (batch.k[c] < h.start[first] || batch.k[c] >= h.start[last]) ++kept.foreign;
    kept.i.insert(kept.i.end(), batch.i, batch.i + n);
    kept.j.insert(kept.j.end(), batch.j, batch.j + n);
    kept.k.insert(kept.k.end(), batch.k, batch.k + n);
    for (int c = 0; c < n; ++c)
      for (int a = 0; a < D; ++a) kept.d.push_back(batch.d[a][c]);
    kept.ri.insert(kept.ri.end(), batch.radius_i, batch.radius_i + n);
    kept.rj.insert(kept.rj.end(), batch.radius_j, batch.radius_j + n);
    n = 0;
  };
  while (w.next < w.end) {
    n = gather_touching<D>(path, in, w, batch, n);
    EXPECT_LE(n, ContactBatch<D>::kSize);
    flush();
  }
  return kept;
}

TYPED_TEST(PairGather, KeepsTheScalarPassPairsAndEndsItsSprings) {
  constexpr int D = TypeParam::value;
  int compared = 0;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const HandList<D> original = hand_list<D>(160, seed);
    const std::size_t rows = original.pos.size();
    for (auto [first, last] :
         {std::pair<std::size_t, std::size_t>{0, rows}, {5, 6}, {7, 8}, {3, 97}, {11, rows - 1}}) {
      SCOPED_TRACE(::testing::Message() << "seed " << seed << ", rows " << first << "-" << last);
      HandList<D> ref = original;
      const Kept want = scalar_pass(ref, first, last);
      for (ContactPath p : {ContactPath::kAvx2, ContactPath::kAvx512}) {
        if (!contact_path_supported(p) || !pair_gather_has(p)) continue;
        SCOPED_TRACE(contact_path_name(p));
        HandList<D> h = original;
        const Kept got = vector_pass(p, h, first, last);
        EXPECT_EQ(got.i, want.i);
        EXPECT_EQ(got.j, want.j);
        EXPECT_EQ(got.k, want.k);
        EXPECT_EQ(got.foreign, 0);
        // What the kernel reads instead of the grains (ContactBatch::measured), to the bit.
        EXPECT_TRUE(same_bits(got.d, want.d));
        EXPECT_TRUE(same_bits(got.ri, want.ri));
        EXPECT_TRUE(same_bits(got.rj, want.rj));
        EXPECT_EQ(std::memcmp(h.spring.data(), ref.spring.data(),
                              h.spring.size() * sizeof(TangentSpring<D>)),
                  0);
        ++compared;
      }
      if (first == 0 && last == rows) {
        // The list reaches what it is for: both outcomes, and springs that end.
        EXPECT_GT(want.k.size(), 100u);
        EXPECT_LT(want.k.size(), original.other.size() / 2);
        EXPECT_NE(std::memcmp(original.spring.data(), ref.spring.data(),
                              ref.spring.size() * sizeof(TangentSpring<D>)),
                  0);
      }
    }
  }
  if (compared == 0) GTEST_SKIP() << "no vector gather path on this processor";
}

}  // namespace
}  // namespace geodem::test
