// Grain mixes (clumps/grain_mix.cpp): the paper's mix of two-disc clumps, four small for
// each large one twice the size, fills its box to the requested solid fraction (exactly,
// without size fuzz, up to the mass-property integration error), with the right counts
// and sizes, and members of different clumps do not overlap (their bounding circles/spheres do
// not).
#include <gtest/gtest.h>

#include <map>

#include "clumps/grain_mix.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class GrainMix : public ::testing::Test {};
TYPED_TEST_SUITE(GrainMix, Dims, DimNames);

TYPED_TEST(GrainMix, PaperMixFillsTheRequestedPorosity) {
  constexpr int D = TypeParam::value;
  GrainSpec spec;
  spec.kinds = {{"pair_0.9", 1.0, 4.0}, {"pair_0.9", 2.0, 1.0}};
  const auto kinds = resolve_kinds<D>(spec);
  World<D> w;
  w.materials = {linear_material(1e5, 5e4, 0.5, 1.0)};
  w.resolve_pair_laws();
  Random rng(7);
  const Vec<D> lo = Vec<D>::Zero(), hi = Vec<D>::Constant(1.0);
  const double porosity = D == 2 ? 0.8 : 0.95;
  const double mean = add_random_grains<D>(w, kinds, lo, hi, 500, porosity, 0.0, 2600.0, 0, rng);
  EXPECT_EQ(w.clumps.size(), 500u);
  EXPECT_EQ(w.particles.size(), 1000u);
  EXPECT_LT(rel_err(solid_volume(w), 1.0 - porosity), 2e-5);
  // Counts and sizes per kind: the larger member radius is the scale.
  std::map<long, int> by_size;
  for (std::size_t i = 0; i < w.particles.size(); ++i) {
    const double r = w.particles.radius[i];
    if (std::abs(r / mean - 1.0) < 1e-12) ++by_size[1];
    if (std::abs(r / mean - 2.0) < 1e-12) ++by_size[2];
  }
  EXPECT_EQ(by_size[1], 400);
  EXPECT_EQ(by_size[2], 100);
  // Bounding spheres apart, hence members of different clumps too.
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    for (std::size_t j = i + 1; j < w.particles.size(); ++j) {
      if (w.particles.clump[i] == w.particles.clump[j]) continue;
      const double d = (w.particles.pos[i] - w.particles.pos[j]).norm();
      ASSERT_GE(d, w.particles.radius[i] + w.particles.radius[j] - 1e-12);
    }
}

}  // namespace
}  // namespace geodem::test
