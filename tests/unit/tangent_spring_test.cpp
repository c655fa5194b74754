// The 2D tangential spring is a signed value along t = (-n_y, n_x) (contacts/neighbour_list.hpp).
// It must give, step after step, the force of the vector spring that is turned with the
// contact plane and rescaled to its magnitude (the 3D form, which 2D used before): here a
// contact is driven through a random history (the normal turning, the overlap and the sliding
// velocity changing sign, sticking and slipping) by both forms side by side.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contacts/contact_law.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

using V2 = Eigen::Vector2d;

// The vector form: project on the new tangent line, keep the magnitude, add kt dt vt, then
// Coulomb (on the spring, or on spring + dashpot when the tangential dashpot is on).
V2 vector_law(const PairLaw& p, double r1, double r2, double inv_msum, const V2& n, double delta,
              const V2& vrel, double dt, V2& spring, double& fn_out) {
  const double vn = vrel.dot(n);
  const NormalResult nr = normal_force(p, r1, r2, inv_msum, delta, vn);
  keep_in_tangent_plane(spring, n);
  const V2 vt = vrel - vn * n;
  spring -= nr.kt * dt * vt;
  const double limit = p.mu * std::max(nr.fn, 0.0);
  fn_out = nr.fn;
  if (!p.tangential_damping) {
    if (spring.norm() > limit) spring *= limit / spring.norm();
    return nr.fn * n + spring;
  }
  V2 ft = spring - nr.cn * vt;
  if (ft.norm() > limit) {
    ft *= limit / ft.norm();
    spring = ft;
  }
  return nr.fn * n + ft;
}

// Drives one contact through `steps` random steps with both forms; returns the largest force
// difference over the largest force.
double largest_difference(const PairLaw& law, int steps, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double r = 0.01, dt = 1e-5, inv_msum = 2.0 / 0.002;
  double angle = 0.3, scalar = 0.0, fmax = 0.0, diff = 0.0;
  V2 vector = V2::Zero();
  double slipping = 0.0;
  for (int s = 0; s < steps; ++s) {
    angle += 0.02 * u(rng);  // the normal turns a little each step
    const V2 n(std::cos(angle), std::sin(angle));
    const double delta = 1e-4 * (1.0 + 0.5 * u(rng));
    // Phases of 200 steps: slow random motion (sticking), then sliding one way or the other
    // along the tangent (slipping once the spring reaches Coulomb's limit).
    const int phase = (s / 200) % 4;
    const V2 t(-n.y(), n.x());
    const V2 vrel = phase % 2 == 0 ? V2(1e-3 * V2(u(rng), u(rng)))
                                   : V2((phase == 1 ? 0.5 : -0.5) * t + 0.1 * V2(u(rng), u(rng)));
    double fn_a = 0.0, fn_b = 0.0;
    const V2 fa = contact_force<2>(law, r, r, inv_msum, n, delta, vrel, dt, scalar, fn_a);
    const V2 fb = vector_law(law, r, r, inv_msum, n, delta, vrel, dt, vector, fn_b);
    EXPECT_EQ(fn_a, fn_b);
    diff = std::max(diff, (fa - fb).norm());
    fmax = std::max(fmax, fb.norm());
    // The stored values are the same spring: the scalar is the vector's component on t.
    EXPECT_NEAR(scalar, vector.dot(t), 1e-9 * std::max(1.0, std::abs(scalar)));
    const double limit = law.mu * std::max(fn_b, 0.0);
    slipping += std::abs((fb - fn_b * n).norm() - limit) < 1e-9 * limit;
  }
  EXPECT_GT(slipping, steps / 10) << "the history must include slipping";
  EXPECT_LT(slipping, steps * 9 / 10) << "the history must include sticking";
  return diff / fmax;
}

TEST(TangentSpring2D, SameForceAsTheVectorTurnedWithThePlane) {
  for (bool dashpot : {false, true}) {
    Material m = linear_material(2e5, 1e5, 0.5, 0.5);
    m.tangential_damping = dashpot;
    const PairLaw law = combine(m, m);
    const double rel = largest_difference(law, 20000, dashpot ? 7 : 8);
    report(std::string("2D scalar against vector tangential spring") +
               (dashpot ? ", with tangential dashpot" : "") + ": largest force difference / force",
           rel);
    EXPECT_LT(rel, 1e-12);
  }
}

// Swapping the two bodies reverses n and the relative velocity: the force on the (new) body 2
// is the opposite, and the stored 2D value is the same from either side.
TEST(TangentSpring2D, SameFromEitherBody) {
  const Material m = linear_material(2e5, 1e5, 0.5, 0.5);
  const PairLaw law = combine(m, m);
  const V2 n = V2(0.6, 0.8), vrel(0.003, -0.001);
  double a = 0.0, b = spring_from_other_body<2>(a), fn = 0.0;
  for (int s = 0; s < 50; ++s) {
    const V2 fa = contact_force<2>(law, 0.01, 0.01, 1000.0, n, 1e-4, vrel, 1e-5, a, fn);
    const V2 fb = contact_force<2>(law, 0.01, 0.01, 1000.0, V2(-n), 1e-4, V2(-vrel), 1e-5, b, fn);
    EXPECT_NEAR((fa + fb).norm(), 0.0, 1e-12 * fa.norm());
    EXPECT_EQ(spring_from_other_body<2>(a), b);
  }
  EXPECT_NE(a, 0.0);
  const Eigen::Vector3d s3(1.0, -2.0, 0.5);
  EXPECT_EQ(spring_from_other_body<3>(s3), Eigen::Vector3d(-s3));
}

// Coulomb's limit of a frictionless contact: the spring becomes zero with the signs that
// scaling by 0 / |ft| gave (the short path skips that square root and division).
TEST(CoulombLimit, FrictionlessSpringScaledByZero) {
  Eigen::Vector3d ft(-3.0e-4, 2.0e-4, 0.0);
  const Eigen::Vector3d before = ft;
  ASSERT_TRUE(limit_to<3>(ft, 0.0));
  const Eigen::Vector3d scaled = before * (0.0 / std::sqrt(before.squaredNorm()));
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(ft[a], 0.0);
    EXPECT_EQ(std::signbit(ft[a]), std::signbit(scaled[a])) << a;
  }
  // With friction: scaled to the limit exactly as before.
  Eigen::Vector3d g(3.0, 4.0, 0.0);
  ASSERT_TRUE(limit_to<3>(g, 2.5));
  EXPECT_DOUBLE_EQ(g.norm(), 2.5);
  EXPECT_EQ(g[0], 3.0 * (2.5 / 5.0));
  // Under the limit: untouched.
  Eigen::Vector3d h(0.1, 0.0, 0.0);
  EXPECT_FALSE(limit_to<3>(h, 0.2));
  EXPECT_EQ(h[0], 0.1);
}

}  // namespace
}  // namespace geodem::test
