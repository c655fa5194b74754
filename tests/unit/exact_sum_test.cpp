// ExactSum (base/exact_sum.hpp): the sum of doubles rounded once, whatever the order of the
// terms and however they were shared between accumulators. References: IEEE addition of two
// doubles is itself correctly rounded, so a two-term ExactSum must equal a + b exactly; sums
// whose exact value is known (terms that cancel, ties) check the rounding of longer sums.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "base/exact_sum.hpp"

namespace geodem {
namespace {

double exact(const std::vector<double>& v) {
  ExactSum s;
  for (double x : v) s.add(x);
  return s.value();
}

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

// Doubles of random sign, significand and exponent in [2^lo, 2^hi).
std::vector<double> random_terms(std::size_t n, int lo, int hi, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> sig(1.0, 2.0);
  std::uniform_int_distribution<int> ex(lo, hi - 1);
  std::vector<double> v(n);
  for (auto& x : v) x = std::ldexp(sig(rng), ex(rng)) * ((rng() & 1) ? -1.0 : 1.0);
  return v;
}

TEST(ExactSum, TwoTermsEqualTheCorrectlyRoundedIeeeSum) {
  // Across the whole range: subnormals, mixed scales, near overflow.
  for (auto [lo, hi] : {std::pair{-1074, -1000}, std::pair{-60, 60}, std::pair{-1074, 1023},
                        std::pair{960, 1023}}) {
    const auto v = random_terms(20000, lo, hi, 7u + static_cast<unsigned>(lo + 2000));
    for (std::size_t i = 0; i + 1 < v.size(); i += 2) {
      ASSERT_EQ(bits(exact({v[i], v[i + 1]})), bits(v[i] + v[i + 1])) << v[i] << " + " << v[i + 1];
      // Normalised first (as a reduction over ranks leaves it): read in place when positive.
      ExactSum s;
      s.add(v[i]), s.add(v[i + 1]), s.normalise();
      ASSERT_EQ(bits(s.value()), bits(v[i] + v[i + 1])) << v[i] << " + " << v[i + 1];
    }
  }
}

TEST(ExactSum, OrderAndSharingDoNotChangeTheBits) {
  auto v = random_terms(5000, -40, 40, 11);
  const double reference = exact(v);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(v.begin(), v.end(), rng);
    EXPECT_EQ(bits(exact(v)), bits(reference));
    // Shared between 1 to 5 accumulators (ranks), merged in any order.
    const std::size_t parts = 1 + static_cast<std::size_t>(trial % 5);
    std::vector<ExactSum> acc(parts);
    for (std::size_t i = 0; i < v.size(); ++i)
      acc[(i * 7 + static_cast<std::size_t>(trial)) % parts].add(v[i]);
    ExactSum total;
    for (std::size_t p = parts; p-- > 0;) total.add(acc[p]);
    EXPECT_EQ(bits(total.value()), bits(reference));
  }
  // And it is the sum: a naive one agrees to its rounding errors.
  double forward = 0.0;
  for (double x : v) forward += x;
  EXPECT_NEAR(forward, reference, 1e-9 * std::abs(reference) + 1e-9);
}

TEST(ExactSum, KnownSumsAreExact) {
  EXPECT_EQ(exact({1e100, 1.0, -1e100}), 1.0);
  // 0.1 + 0.2 - 0.3 over the three doubles: 0.1 + 0.2 = s + err exactly (Knuth's TwoSum), and
  // s - 0.3 is exact (Sterbenz), so the correctly rounded sum is (s + c) + err.
  const double a = 0.1, b = 0.2, c = -0.3;
  const double s = a + b, bb = s - a, err = (a - (s - bb)) + (b - bb);
  EXPECT_EQ(exact({a, b, c}), (s + c) + err);
  // Terms that cancel in pairs leave the odd one out, whatever their scales.
  auto v = random_terms(4000, -1074, 1020, 5);
  std::vector<double> w;
  for (double x : v) w.push_back(x), w.push_back(-x);
  w.push_back(std::ldexp(1.0, -1074));
  std::shuffle(w.begin(), w.end(), std::mt19937(9));
  EXPECT_EQ(exact(w), std::ldexp(1.0, -1074));
  EXPECT_EQ(exact({}), 0.0);
  EXPECT_EQ(exact({-2.5, -0.25}), -2.75);
}

TEST(ExactSum, RoundsToNearestWithTiesToEven) {
  const double big = std::ldexp(1.0, 53);                        // spacing 2 above it
  EXPECT_EQ(exact({big, 1.0}), big);                             // tie: to even
  EXPECT_EQ(exact({big, 1.0, std::ldexp(1.0, -200)}), big + 2);  // just past the tie: up
  EXPECT_EQ(exact({big + 2, 1.0}), big + 4);                     // tie: to even (up)
  EXPECT_EQ(exact({-big, -1.0, -std::ldexp(1.0, -200)}), -(big + 2));
  const double max = std::numeric_limits<double>::max();
  EXPECT_EQ(exact({max, max, -max}), max);  // no overflow in between
  EXPECT_EQ(exact({max, max}), std::numeric_limits<double>::infinity());
}

// A reduction over ranks packs each rank's sums over the window of digits any of them uses
// (MpiDomainComm::sum) and adds the packed limbs: the same bits as merging the whole sums,
// with negative, infinite and normalised sums; and over all the digits (the window a normalised
// negative sum makes: its digits reach the top).
TEST(ExactSum, PackedOverTheirWindowTheSumsMergeToTheSameBits) {
  constexpr int kRanks = 3;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<ExactSum>> ranks(kRanks, std::vector<ExactSum>(4));
  for (int r = 0; r < kRanks; ++r) {
    auto& s = ranks[static_cast<std::size_t>(r)];
    for (double x : random_terms(300, -30, 10, 20u + static_cast<unsigned>(r))) s[0].add(x);
    for (double x : random_terms(50, 0, 3, 30u + static_cast<unsigned>(r))) s[1].add(-std::abs(x));
    s[2].add(r == 1 ? inf : 1e-3);
    for (double x : random_terms(40, -5, 5, 40u + static_cast<unsigned>(r))) s[3].add(std::abs(x));
    if (r == 2) s[3].normalise();  // (a positive sum: its digits stay in its span)
  }
  // The whole sums merged: the reference.
  std::vector<ExactSum> whole(4);
  for (const auto& s : ranks)
    for (std::size_t k = 0; k < 4; ++k) whole[k].add(s[k]);
  for (bool wide : {false, true}) {
    int lo = ExactSum::kDigits, hi = 0;
    if (wide) {
      lo = 0, hi = ExactSum::kDigits;
    } else {
      for (const auto& s : ranks)
        for (const auto& x : s) {
          int a = 0, b = 0;
          x.digit_span(a, b);
          if (a < b) lo = std::min(lo, a), hi = std::max(hi, b);
        }
      EXPECT_LT(lo, hi);
      EXPECT_LT(hi - lo, 12);  // a few digits of 68
    }
    const std::size_t width = static_cast<std::size_t>(hi - lo + 3);
    std::vector<std::int64_t> total(4 * width, 0), packed(total.size());
    for (const auto& s : ranks) {
      ExactSum::pack(s, lo, hi, packed.data());
      for (std::size_t k = 0; k < total.size(); ++k) total[k] += packed[k];
    }
    std::vector<ExactSum> merged(4);
    ExactSum::unpack(total.data(), lo, hi, merged);
    for (std::size_t k = 0; k < 4; ++k) {
      merged[k].normalise();
      EXPECT_EQ(bits(merged[k].value()), bits(whole[k].value())) << "sum " << k;
    }
  }
  EXPECT_EQ(whole[2].value(), inf);
}

TEST(ExactSum, InfinitiesAndNaN) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(exact({1.0, inf}), inf);
  EXPECT_EQ(exact({1.0, -inf}), -inf);
  EXPECT_TRUE(std::isnan(exact({inf, -inf})));
  EXPECT_TRUE(std::isnan(exact({1.0, std::nan("")})));
}

}  // namespace
}  // namespace geodem
