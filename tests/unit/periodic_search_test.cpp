// The periodic cell's neighbour search against brute force: grains scattered in and beyond
// a rectangular and a sheared cell, with two-grain clumps whose members straddle the faces
// (a clump is moved back into the cell by its centre, so a member may stay outside); after a
// build every pair of grains within r_i + r_j + skin through some image (m in {-1, 0, 1}^D)
// is listed once with that image, members of one clump never, and nothing else.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include "broadphase/neighbour_search.hpp"
#include "clumps/clump_template.hpp"
#include "clumps/clumps.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class PeriodicSearchTest : public ::testing::Test {};
TYPED_TEST_SUITE(PeriodicSearchTest, Dims, DimNames);

template <int D>
World<D> scattered(bool sheared, std::uint64_t seed) {
  World<D> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 0.5));
  w.resolve_pair_laws();
  w.cell.periodic = true;
  const double side = D == 2 ? 30.0 : 12.0;
  w.cell.h = Dim<D>::Tensor::Identity() * side;
  if (sheared) w.cell.h(0, 1) = 0.35 * side;  // leaning by about 19 degrees
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.3, 1.3);  // some beyond the faces
  auto somewhere = [&] {
    Vec<D> s;
    for (int k = 0; k < D; ++k) s[k] = u(rng);
    return Vec<D>(w.cell.h * s);
  };
  const std::size_t singles = D == 2 ? 250 : 300;
  for (std::size_t i = 0; i < singles; ++i)
    w.particles.add(somewhere(), 0.4 + 0.6 * std::uniform_real_distribution<double>(0, 1)(rng),
                    1000.0, mat);
  ClumpTemplate<D> t;
  t.centre = {Vec<D>::Zero(), Vec<D>(1.4 * axis<D>(0))};
  t.radius = {1.0, 0.8};
  const ResolvedClump<D> pair = resolve_clump(t);
  for (int c = 0; c < 100; ++c)
    add_clump(w, pair, somewhere(), Dim<D>::identity(), 1.0, 1000.0, mat);
  return w;
}

template <int D>
void check(World<D>& w) {
  build_neighbour_list(w);
  const auto& P = w.particles;
  const auto& L = w.nlist;
  ASSERT_EQ(L.image.size(), L.other.size());
  std::set<std::tuple<std::size_t, std::size_t, int, int, int>> listed, want;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const auto& m = L.image[k].m;
      EXPECT_TRUE(listed.insert({i, L.other[k], m[0], m[1], m[2]}).second) << "listed twice";
      EXPECT_GT(L.other[k], i);
    }
  std::size_t crossing = 0, outside_members = 0;
  const auto h_inv = w.cell.h.inverse();
  for (std::size_t i = 0; i < P.size(); ++i) {
    const Vec<D> s = h_inv * P.pos[i];
    outside_members += P.member(i) && (s.minCoeff() < 0.0 || s.maxCoeff() >= 1.0);
    for (std::size_t j = i + 1; j < P.size(); ++j) {
      if (P.member(i) && P.clump[i] == P.clump[j]) continue;
      const double reach = P.radius[i] + L.skin + P.radius[j];
      for (int a = -2; a <= 2; ++a)
        for (int b = -2; b <= 2; ++b)
          for (int c = (D == 3 ? -2 : 0); c <= (D == 3 ? 2 : 0); ++c) {
            CellImage m;
            m.m = {static_cast<std::int8_t>(a), static_cast<std::int8_t>(b),
                   static_cast<std::int8_t>(c)};
            if ((P.pos[j] + w.cell.shift(m) - P.pos[i]).squaredNorm() < reach * reach) {
              want.insert({i, j, a, b, c});
              crossing += !m.home();
            }
          }
    }
  }
  EXPECT_EQ(listed, want);
  EXPECT_GT(crossing, 10u);
  EXPECT_GT(outside_members, 0u);  // the case the binning must get right
  report(std::to_string(D) + "D periodic search: pairs, through the faces, members outside",
         static_cast<double>(want.size() * 1000000 + crossing * 1000 + outside_members));
}

TYPED_TEST(PeriodicSearchTest, MatchesBruteForceInARectangularCell) {
  for (std::uint64_t seed : {1, 2, 3}) {
    World<TypeParam::value> w = scattered<TypeParam::value>(false, seed);
    check(w);
  }
}

TYPED_TEST(PeriodicSearchTest, MatchesBruteForceInAShearedCell) {
  for (std::uint64_t seed : {4, 5, 6}) {
    World<TypeParam::value> w = scattered<TypeParam::value>(true, seed);
    check(w);
  }
}

}  // namespace
}  // namespace geodem::test
