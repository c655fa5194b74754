// The cuts of a rebalanced domain (domain/balanced_cuts.hpp) against work laid out by hand:
// where equal shares fall, the damped move, the ghost-width limits, and repeated moves on a
// steady load approaching the balanced cut without passing it.
#include "domain/balanced_cuts.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace geodem {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Work with density 1 on [0, 0.5) and 2 on [0.5, 1), in `bins` bins over [0, 1), a bin's
// work split where a cut lies inside it.
std::vector<double> step_load(std::size_t bins) {
  std::vector<double> w(bins);
  for (std::size_t b = 0; b < bins; ++b) {
    const double lo = static_cast<double>(b) / static_cast<double>(bins);
    const double hi = static_cast<double>(b + 1) / static_cast<double>(bins);
    w[b] = std::max(0.0, std::min(hi, 0.5) - lo) + 2.0 * std::max(0.0, hi - std::max(lo, 0.5));
  }
  return w;
}

TEST(BalancedCuts, EqualSharesOfAStepLoad) {
  // Total 1.5: half of it (0.75) lies below x = 0.5 + 0.25 / 2 = 0.625; thirds (0.5, 1.0) at
  // x = 0.5 and 0.75.
  const auto w = step_load(1024);
  const auto two = balanced_cuts(w, {-kInf, 0.5, kInf}, 0.0, 1.0, 0.01, 1.0);
  EXPECT_NEAR(two[1], 0.625, 1e-12);
  EXPECT_EQ(two[0], -kInf);
  EXPECT_EQ(two[2], kInf);
  const auto three = balanced_cuts(w, {-kInf, 0.3, 0.6, kInf}, 0.0, 1.0, 0.01, 1.0);
  EXPECT_NEAR(three[1], 0.5, 1e-12);
  EXPECT_NEAR(three[2], 0.75, 1e-12);
}

TEST(BalancedCuts, DampedMoveGoesPartOfTheWay) {
  const auto w = step_load(1024);
  const auto half = balanced_cuts(w, {-kInf, 0.5, kInf}, 0.0, 1.0, 0.01, 0.5);
  EXPECT_NEAR(half[1], 0.5625, 1e-12);  // half of the way from 0.5 to 0.625
  // The domain's own offset and span: x in [2, 6) maps the same load four times as wide.
  const auto wide = balanced_cuts(w, {-kInf, 4.0, kInf}, 2.0, 4.0, 0.01, 0.5);
  EXPECT_NEAR(wide[1], 4.25, 1e-12);
}

TEST(BalancedCuts, RepeatedMovesApproachWithoutPassing) {
  // The same steady load measured again after each move: the cut approaches 0.625 from below
  // at half the remaining distance a move, never beyond it.
  const auto w = step_load(1024);
  std::vector<double> cuts{-kInf, 0.2, kInf};
  double gap = 0.625 - 0.2;
  for (int k = 0; k < 30; ++k) {
    cuts = balanced_cuts(w, cuts, 0.0, 1.0, 0.01, 0.5);
    EXPECT_LE(cuts[1], 0.625 + 1e-12);
    EXPECT_NEAR(0.625 - cuts[1], 0.5 * gap, 1e-12);
    gap = 0.625 - cuts[1];
  }
  EXPECT_NEAR(cuts[1], 0.625, 1e-9);
}

TEST(BalancedCuts, CutsKeepAGhostWidthFromTheirNeighbours) {
  // All the work in the first bin would pull both cuts to x = 0: each stops a ghost width
  // (0.1) above its lower neighbour's old cut (so that no grain passes two ranks in one
  // build): the first at 0.1, the second at 0.5 (not at 0.2, above the first one's new place).
  std::vector<double> w(100, 0.0);
  w[0] = 1.0;
  const auto cuts = balanced_cuts(w, {0.0, 0.4, 0.7, 1.0}, 0.0, 1.0, 0.1, 1.0);
  EXPECT_NEAR(cuts[1], 0.1, 1e-12);
  EXPECT_NEAR(cuts[2], 0.5, 1e-12);
  // Work at the top end: each cut at most a ghost width below its old upper neighbour.
  std::vector<double> top(100, 0.0);
  top[99] = 1.0;
  const auto up = balanced_cuts(top, {0.0, 0.4, 0.7, 1.0}, 0.0, 1.0, 0.1, 1.0);
  EXPECT_NEAR(up[1], 0.6, 1e-12);
  EXPECT_NEAR(up[2], 0.9, 1e-12);
  // Less than two ghost widths between a cut's neighbours (slabs that grains grew into): no
  // place is allowed, and the cut stays.
  const auto stuck = balanced_cuts(w, {0.0, 0.1, 0.19, 1.0}, 0.0, 1.0, 0.1, 1.0);
  EXPECT_EQ(stuck[1], 0.1);
}

TEST(BalancedCuts, NoWorkMovesNothing) {
  const std::vector<double> old{-kInf, 0.3, 0.6, kInf};
  EXPECT_EQ(balanced_cuts(std::vector<double>(64, 0.0), old, 0.0, 1.0, 0.01, 1.0), old);
  EXPECT_EQ(balanced_cuts(step_load(64), {-kInf, kInf}, 0.0, 1.0, 0.01, 1.0),
            (std::vector<double>{-kInf, kInf}));
}

TEST(BalancedCuts, ImbalanceAgainstAnEvenShare) {
  EXPECT_FALSE(imbalanced({1.0, 1.04}, 0.05));    // slowest 1.04 against a share of 1.02
  EXPECT_TRUE(imbalanced({1.0, 1.2}, 0.05));      // 1.2 against 1.1: 9 % over
  EXPECT_TRUE(imbalanced({1.0, 1.0, 1.4}, 0.1));  // 1.4 against 1.133
  EXPECT_FALSE(imbalanced({0.0, 0.0}, 0.05));
  EXPECT_FALSE(imbalanced({}, 0.05));
  EXPECT_NEAR(busiest_share({1.0, 1.2}), 2.4 / 2.2, 1e-15);
  EXPECT_NEAR(busiest_share({2.0, 2.0, 2.0}), 1.0, 1e-15);
  EXPECT_EQ(busiest_share({0.0, 0.0}), 0.0);
}

}  // namespace
}  // namespace geodem
