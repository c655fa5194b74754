// Grains given one by one that overlap beyond the limit are an input error naming both
// (scene/input_overlaps.hpp): against a brute-force search over every earlier grain, on random
// clouds in 2D and 3D, with a far outlier that makes the cells grow, and with none too deep.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "scene/input_overlaps.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class InputOverlaps : public ::testing::Test {};
TYPED_TEST_SUITE(InputOverlaps, Dims, DimNames);

std::string grain_name(std::size_t k) {
  return "grain " + std::to_string(k);
}

// The first grain a that overlaps an earlier one beyond the limit, with the earliest such
// earlier grain; {n, n} if none.
template <int D>
std::pair<std::size_t, std::size_t> brute_force(const std::vector<Sphere<D>>& g, double limit) {
  for (std::size_t a = 0; a < g.size(); ++a)
    for (std::size_t b = 0; b < a; ++b) {
      const double smaller = std::min(g[a].radius, g[b].radius);
      const double depth = g[a].radius + g[b].radius - (g[a].centre - g[b].centre).norm();
      if (depth > limit * smaller) return {a, b};
    }
  return {g.size(), g.size()};
}

template <int D>
std::vector<Sphere<D>> cloud(std::size_t n, double side, std::uint64_t seed, bool outlier) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, side), r(0.3, 1.0);
  std::vector<Sphere<D>> g(n);
  for (auto& s : g) {
    for (int k = 0; k < D; ++k) s.centre[k] = u(rng);
    s.radius = r(rng);
  }
  if (outlier) g[n / 2].centre[0] = 1e7;  // the cells grow until there are about 2 per grain
  return g;
}

TYPED_TEST(InputOverlaps, FirstOffenderAndEarliestPartnerAsBruteForceFinds) {
  constexpr int D = TypeParam::value;
  const double limit = 0.5;
  int thrown = 0, clear = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed)
    for (bool outlier : {false, true}) {
      // Dense enough that some clouds hold a deep overlap and some none.
      const double side = D == 3 ? 60.0 : 300.0;
      const auto g = cloud<D>(300, side, seed, outlier);
      const auto want = brute_force<D>(g, limit);
      if (want.first == g.size()) {
        EXPECT_NO_THROW(reject_input_overlaps<D>(g, grain_name, limit, "s.toml")) << seed;
        ++clear;
        continue;
      }
      try {
        reject_input_overlaps<D>(g, grain_name, limit, "s.toml");
        ADD_FAILURE() << "seed " << seed << ": no error, brute force finds grains " << want.first
                      << " and " << want.second;
      } catch (const InputError& e) {
        ++thrown;
        EXPECT_EQ(e.key(), grain_name(want.first)) << seed;
        EXPECT_NE(e.detail().find("overlaps " + grain_name(want.second) + " by "),
                  std::string::npos)
            << e.detail();
        EXPECT_EQ(e.file(), "s.toml");
      }
    }
  EXPECT_GT(thrown, 5);  // both cases were met
  EXPECT_GT(clear, 5);
}

TYPED_TEST(InputOverlaps, TouchingAndShallowOverlapsPass) {
  constexpr int D = TypeParam::value;
  // A row of grains, each overlapping the next by 40 % of the radius: below a 50 % limit.
  std::vector<Sphere<D>> g(50);
  for (std::size_t i = 0; i < g.size(); ++i) {
    g[i].centre = Vec<D>::Zero();
    g[i].centre[0] = 1.6 * static_cast<double>(i);
    g[i].radius = 1.0;
  }
  EXPECT_NO_THROW(reject_input_overlaps<D>(g, grain_name, 0.5, "s.toml"));
  // The last one moved onto its neighbour: 60 % of the radius.
  g.back().centre[0] -= 0.2;
  try {
    reject_input_overlaps<D>(g, grain_name, 0.5, "s.toml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "grain 49");
    EXPECT_NE(e.detail().find("overlaps grain 48 by 60 %"), std::string::npos) << e.detail();
  }
}

}  // namespace
}  // namespace geodem::test
