// The move of the grains by the vector kernels (integrate/move_kernel.hpp) gives the scalar
// loop's bits: positions, velocities, spins and the bound on the displacement after steps of
// integrate() on every path the machine runs, with and without local damping, with gravity,
// with fixed grains, clump members and ghosts among free ones, and a count of grains that
// leaves some after the last whole block.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "contacts/contact_batch.hpp"
#include "integrate/integrator.hpp"
#include "moving_worlds.hpp"
#include "particles/particles.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class MoveKernel : public ::testing::Test {};
TYPED_TEST_SUITE(MoveKernel, Dims, DimNames);

template <int D>
World<D> random_grains(double damping, std::size_t n) {
  World<D> w;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto rvec = [&] {
    Vec<D> v;
    for (int k = 0; k < D; ++k) v[k] = u(rng);
    return v;
  };
  auto rrot = [&] {
    typename Dim<D>::Rot r;
    if constexpr (D == 2) {
      r = u(rng);
    } else {
      r = typename Dim<D>::Rot(u(rng), u(rng), u(rng));
    }
    return r;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const bool fixed = i % 11 == 3;
    const std::size_t g =
        w.particles.add(rvec(), 0.01 * (1.0 + 0.5 * u(rng)), 2600.0, 0, rvec(), rrot(), fixed);
    if (i % 13 == 5) w.particles.flags[g] |= kClumpMember;
    if (i % 17 == 9) w.particles.flags[g] |= kGhost;
    // Zero components of either sign: the scalar loop's sums keep their signs.
    if (i % 7 == 2) w.particles.vel[g][0] = -0.0;
  }
  w.dt = 1e-5;
  w.local_damping = damping;
  w.gravity = Vec<D>::Zero();
  w.gravity[D - 1] = -9.81;
  return w;
}

// Steps with fresh random forces (the same on every path).
template <int D>
void run_steps(World<D>& w) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int s = 0; s < 20; ++s) {
    for (std::size_t i = 0; i < w.particles.size(); ++i) {
      for (int k = 0; k < D; ++k) w.particles.force[i][k] = s % 5 == 0 ? 0.0 : u(rng);
      if constexpr (D == 2) {
        w.particles.torque[i] = 1e-3 * u(rng);
      } else {
        for (int k = 0; k < 3; ++k) w.particles.torque[i][k] = 1e-3 * u(rng);
      }
    }
    integrate(w);
  }
}

TYPED_TEST(MoveKernel, EveryPathGivesTheScalarLoopsBits) {
  constexpr int D = TypeParam::value;
  ContactPathGuard guard;
  int paths = 0;
  for (double damping : {0.0, 0.2}) {
    for (std::size_t n : {std::size_t{5}, std::size_t{8}, std::size_t{203}}) {
      ASSERT_TRUE(set_contact_path(ContactPath::kScalar));
      World<D> ref = random_grains<D>(damping, n);
      run_steps(ref);
      for (ContactPath p : {ContactPath::kAvx2, ContactPath::kAvx512}) {
        if (!set_contact_path(p)) continue;
        ++paths;
        World<D> w = random_grains<D>(damping, n);
        run_steps(w);
        SCOPED_TRACE(std::string(contact_path_name(p)) + ", damping " + std::to_string(damping) +
                     ", " + std::to_string(n) + " grains");
        EXPECT_TRUE(same_bits(w.particles.pos, ref.particles.pos));
        EXPECT_TRUE(same_bits(w.particles.vel, ref.particles.vel));
        EXPECT_TRUE(same_bits(w.particles.angvel, ref.particles.angvel));
        EXPECT_EQ(std::memcmp(&w.disp_bound, &ref.disp_bound, sizeof(double)), 0);
        EXPECT_GT(w.disp_bound, 0.0);
      }
    }
  }
  if (paths == 0) GTEST_SKIP() << "this processor runs neither AVX2 nor AVX-512";
}

// The moves themselves, on one grain: v += (F/m + g) dt, x += v dt (semi-implicit Euler).
TYPED_TEST(MoveKernel, FreeGrainFollowsSemiImplicitEuler) {
  constexpr int D = TypeParam::value;
  ContactPathGuard guard;
  for (ContactPath p : {ContactPath::kScalar, ContactPath::kAvx2, ContactPath::kAvx512}) {
    if (!set_contact_path(p)) continue;
    World<D> w = random_grains<D>(0.0, 16);
    const std::size_t i = 0;  // a free grain (not fixed, no clump, no ghost)
    ASSERT_EQ(w.particles.flags[i], 0);
    const Vec<D> v0 = w.particles.vel[i], x0 = w.particles.pos[i];
    Vec<D> f = Vec<D>::Zero();
    f[0] = 2.0;
    w.particles.force[i] = f;
    integrate(w);
    const double m = 1.0 / w.particles.inv_mass[i];
    const Vec<D> v1 = v0 + (f / m + w.gravity) * w.dt;
    EXPECT_LT((w.particles.vel[i] - v1).norm(), 1e-14) << contact_path_name(p);
    EXPECT_LT((w.particles.pos[i] - (x0 + v1 * w.dt)).norm(), 1e-14) << contact_path_name(p);
  }
}

}  // namespace
}  // namespace geodem::test
