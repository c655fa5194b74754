// The instability watch (world/step.cpp, check_finite): a grain that went through a wall,
// or a contact that closes by half a radius in one step, stops the run with a diagnosis;
// fast grains in free flight, or moving together, do not.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "base/error.hpp"
#include "broadphase/neighbour_search.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class Instability : public ::testing::Test {};
TYPED_TEST_SUITE(Instability, Dims, DimNames);

constexpr double kR = 0.01, kRho = 2600.0;

template <int D>
World<D> two_grains(double gap) {
  World<D> w;
  const auto m = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0, kRho));
  add_plane(w, vec<D>(0.0, -1.0, 0.0), vec<D>(0.0, 1.0, 0.0), m, "floor");
  w.resolve_pair_laws();
  w.particles.add(vec<D>(0.0, 0.0, 0.0), kR, kRho, m);
  w.particles.add(vec<D>(2.0 * kR + gap, 0.0, 0.0), kR, kRho, m);
  w.dt = 1e-3;
  build_neighbour_list(w);
  return w;
}

template <int D>
std::string diagnosis(const World<D>& w) {
  try {
    check_finite(w);
  } catch (const InstabilityError& e) {
    return e.what();
  }
  return "";
}

TYPED_TEST(Instability, ContactClosingByHalfARadiusPerStepIsRunaway) {
  constexpr int D = TypeParam::value;
  World<D> w = two_grains<D>(-1e-4 * kR);  // touching
  // 0.6 radii per step of approach: runaway.
  w.particles.vel[0] = vec<D>(0.3 * kR / w.dt, 0.0, 0.0);
  w.particles.vel[1] = vec<D>(-0.3 * kR / w.dt, 0.0, 0.0);
  const std::string d = diagnosis(w);
  EXPECT_NE(d.find("runaway grain"), std::string::npos) << d;
  EXPECT_NE(d.find("time step"), std::string::npos) << d;
  // 0.4 radii per step: resolved.
  w.particles.vel[0] *= 0.4 / 0.6, w.particles.vel[1] *= 0.4 / 0.6;
  EXPECT_EQ(diagnosis(w), "");
}

TYPED_TEST(Instability, FastGrainsInFlightOrTogetherAreNot) {
  constexpr int D = TypeParam::value;
  World<D> apart = two_grains<D>(0.5 * kR);
  apart.particles.vel[0] = vec<D>(0.0, 5.0 * kR / apart.dt, 0.0);  // 5 radii per step, alone
  EXPECT_EQ(diagnosis(apart), "");
  World<D> together = two_grains<D>(-1e-4 * kR);
  for (auto& v : together.particles.vel) v = vec<D>(0.0, 3.0 * kR / together.dt, 0.0);
  EXPECT_EQ(diagnosis(together), "");
}

TYPED_TEST(Instability, GrainBehindAPlaneWallEscaped) {
  constexpr int D = TypeParam::value;
  World<D> w = two_grains<D>(0.5 * kR);
  EXPECT_EQ(diagnosis(w), "");
  w.particles.pos[1] = vec<D>(0.0, -1.0 - 1.5 * kR, 0.0);  // wholly below the floor
  const std::string d = diagnosis(w);
  EXPECT_NE(d.find("grain 1 escaped through wall 'floor'"), std::string::npos) << d;
}

TYPED_TEST(Instability, NonFiniteState) {
  constexpr int D = TypeParam::value;
  World<D> w = two_grains<D>(0.5 * kR);
  w.particles.vel[0][0] = std::numeric_limits<double>::quiet_NaN();
  const std::string d = diagnosis(w);
  EXPECT_NE(d.find("non-finite state"), std::string::npos) << d;
  EXPECT_NE(d.find("grain 0"), std::string::npos) << d;
}

}  // namespace
}  // namespace geodem::test
