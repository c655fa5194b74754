// A grain on a plane tilted by theta under vertical gravity. With I = f m R^2 it rolls
// without slip while the friction it needs, f/(1+f) m g sin(theta), stays below
// mu m g cos(theta), i.e. tan(theta) < mu (1+f)/f (3.5 mu sphere, 3 mu disc), with
//   a = g sin(theta) / (1 + f)     (5/7 g sin(theta) sphere, 2/3 g sin(theta) disc);
// above that it slides with a = g (sin(theta) - mu cos(theta)).
//
// With rolling resistance (tests at the end), the threshold moves to tan(theta) = eta.
//
// The grain starts touching the plane and first settles on it with gravity along the
// plane's normal and local damping; then gravity turns vertical and damping off. The
// tangential spring starts unloaded, so its force oscillates (undamped) about the mean;
// the acceleration is the least-squares slope of the downhill velocity over some 300
// periods of that oscillation, which averages it out.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace geodem::test {
namespace {

constexpr double kG = 9.81, kRadius = 0.01, kDensity = 2600.0;

template <typename T>
class Incline : public ::testing::Test {};
TYPED_TEST_SUITE(Incline, Dims, DimNames);

struct InclineResult {
  double accel;       // downhill acceleration of the centre
  double spin_accel;  // angular acceleration (magnitude)
  double slip;        // contact-point speed / centre speed at the end
};

// `eta`: rolling friction of grain and plane (0: none).
template <int D>
InclineResult run_incline(double theta, double mu, double eta = 0.0) {
  World<D> w;
  const double m = kDensity * Dim<D>::volume(kRadius);
  // Stiff: static overlap 1e-5 R, so the lever arm is R.
  const double kn = m * kG / (1e-5 * kRadius);
  Material gm = linear_material(kn, 0.5 * kn, mu, 0.5, kDensity);
  Material pm = linear_material(kn, 0.5 * kn, 10.0, 1.0, kDensity, "plane");
  gm.rolling_friction = pm.rolling_friction = eta;
  const auto grain = add_material(w, gm);
  const auto plane = add_material(w, pm);
  const Vec<D> n = vec<D>(std::sin(theta), std::cos(theta));
  const Vec<D> downhill = vec<D>(std::cos(theta), -std::sin(theta));
  add_plane(w, Vec<D>::Zero(), n, plane, "incline");
  w.resolve_pair_laws();
  w.dt = 0.05 * std::sqrt(m / kn);
  w.particles.add(Vec<D>(kRadius * n), kRadius, kDensity, grain);

  // Settle on the plane.
  w.gravity = -kG * std::cos(theta) * n;
  w.local_damping = 0.7;
  for (int k = 0; k < 4000; ++k) step(w);
  EXPECT_LT(rel_err(overlap(w), m * kG * std::cos(theta) / kn), 1e-6);
  EXPECT_LT(w.particles.vel[0].norm(), 1e-9);

  // Release: vertical gravity, no damping.
  w.gravity = vec<D>(0.0, -kG);
  w.local_damping = 0.0;
  const double omega_t = std::sqrt((1.0 + 1.0 / Dim<D>::inertia_factor()) * 0.5 * kn / m);
  const int steps = static_cast<int>(300 * 2.0 * std::numbers::pi / (omega_t * w.dt));
  double st = 0, sv = 0, stt = 0, stv = 0, sw = 0, stw = 0;
  for (int k = 0; k < steps; ++k) {
    step(w);
    const double t = w.time - 0.5 * w.dt;  // the velocities are at half steps
    const double v = w.particles.vel[0].dot(downhill);
    const double spin = std::abs(spin_z<D>(w.particles.angvel[0]));
    st += t, sv += v, stt += t * t, stv += t * v, sw += spin, stw += t * spin;
  }
  const double nk = steps, den = nk * stt - st * st;
  InclineResult r;
  r.accel = (nk * stv - st * sv) / den;
  r.spin_accel = (nk * stw - st * sw) / den;
  const auto& P = w.particles;
  const Vec<D> contact_vel = P.vel[0] + Dim<D>::cross(P.angvel[0], Vec<D>(-kRadius * n));
  r.slip = contact_vel.norm() / P.vel[0].norm();
  // Stayed on the plane.
  EXPECT_LT(rel_err(overlap(w), m * kG * std::cos(theta) / kn), 0.05);
  return r;
}

TYPED_TEST(Incline, RollsWithoutSlipBelowThreshold) {
  constexpr int D = TypeParam::value;
  const double theta = 20.0 * std::numbers::pi / 180.0, mu = 0.5;
  const double f = Dim<D>::inertia_factor();
  ASSERT_LT(std::tan(theta), mu * (1.0 + f) / f);
  const InclineResult r = run_incline<D>(theta, mu);
  const double a_want = kG * std::sin(theta) / (1.0 + f);  // 5/7 or 2/3 g sin(theta)
  report(std::to_string(D) + "D incline rolling acceleration", rel_err(r.accel, a_want));
  report(std::to_string(D) + "D incline rolling slip / speed", r.slip);
  EXPECT_LT(rel_err(r.accel, a_want), 0.01);
  EXPECT_LT(rel_err(r.spin_accel, a_want / kRadius), 0.01);
  EXPECT_LT(r.slip, 0.01);
}

TYPED_TEST(Incline, SlidesAboveThreshold) {
  constexpr int D = TypeParam::value;
  const double theta = 30.0 * std::numbers::pi / 180.0, mu = 0.1;
  const double f = Dim<D>::inertia_factor();
  ASSERT_GT(std::tan(theta), mu * (1.0 + f) / f);
  const InclineResult r = run_incline<D>(theta, mu);
  const double a_want = kG * (std::sin(theta) - mu * std::cos(theta));
  // Friction mu m g cos(theta) spins the grain up: alpha = mu g cos(theta) / (f R).
  const double alpha_want = mu * kG * std::cos(theta) / (f * kRadius);
  report(std::to_string(D) + "D incline sliding acceleration", rel_err(r.accel, a_want));
  report(std::to_string(D) + "D incline sliding angular acceleration",
         rel_err(r.spin_accel, alpha_want));
  EXPECT_LT(rel_err(r.accel, a_want), 0.01);
  EXPECT_LT(rel_err(r.spin_accel, alpha_want), 0.01);
  EXPECT_GT(r.slip, 0.3);
}

// Rolling resistance: the rolling moment is limited to eta fn R (R = r against a wall).
// At rest the moment must balance m g sin(theta) R about the centre (the friction force
// carries the downhill weight), so the grain stays put while tan(theta) < eta; above,
// the moment is eta m g cos(theta) R and it rolls with
//   a = g (sin(theta) - eta cos(theta)) / (1 + f).
TYPED_TEST(Incline, RollingResistanceHoldsBelowThreshold) {
  constexpr int D = TypeParam::value;
  const double eta = 0.2, theta = std::atan(0.8 * eta);
  const InclineResult r = run_incline<D>(theta, 1.0, eta);
  const double a_free = kG * std::sin(theta) / (1.0 + Dim<D>::inertia_factor());
  report(std::to_string(D) + "D rolling resistance below threshold: a / a_free",
         std::abs(r.accel) / a_free);
  EXPECT_LT(std::abs(r.accel), 1e-3 * a_free);
  EXPECT_LT(std::abs(r.spin_accel) * kRadius, 1e-3 * a_free);
}

TYPED_TEST(Incline, RollingResistanceRollsAboveThreshold) {
  constexpr int D = TypeParam::value;
  const double eta = 0.2, theta = std::atan(1.5 * eta);
  const InclineResult r = run_incline<D>(theta, 1.0, eta);
  const double f = Dim<D>::inertia_factor();
  const double a_want = kG * (std::sin(theta) - eta * std::cos(theta)) / (1.0 + f);
  report(std::to_string(D) + "D rolling resistance above threshold: acceleration",
         rel_err(r.accel, a_want));
  EXPECT_LT(rel_err(r.accel, a_want), 0.01);
  EXPECT_LT(rel_err(r.spin_accel, a_want / kRadius), 0.01);
  EXPECT_LT(r.slip, 0.01);
}

}  // namespace
}  // namespace geodem::test
