// Free fall against the exact kinematics, and a grain at rest on a floor carrying its weight.
//
// The leapfrog stores v at half steps: started from v(-dt/2) = v0 - g dt/2, it reproduces
// x(t) = x0 + v0 t + g t^2/2 exactly at every step (constant acceleration); started from
// v(-dt/2) = v0 instead, it is ahead by exactly g dt t / 2.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class FreeFall : public ::testing::Test {};
TYPED_TEST_SUITE(FreeFall, Dims, DimNames);

template <int D>
World<D> falling_grain(const Vec<D>& x0, const Vec<D>& v_half, const Vec<D>& g, double dt) {
  World<D> w;
  add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  w.gravity = g;
  w.dt = dt;
  w.particles.add(x0, 0.01, 2600.0, 0, v_half);
  return w;
}

TYPED_TEST(FreeFall, ExactLeapfrogKinematics) {
  constexpr int D = TypeParam::value;
  const Vec<D> g = vec<D>(0.3, -9.81, 0.2);
  const Vec<D> x0 = vec<D>(1.0, 2.0, -0.5), v0 = vec<D>(0.5, 3.0, -1.0);
  const double dt = 1e-4;
  const int steps = 20000;
  World<D> w = falling_grain<D>(x0, v0 - 0.5 * dt * g, g, dt);
  double err_x = 0.0, err_v = 0.0;
  for (int k = 1; k <= steps; ++k) {
    step(w);
    const double t = k * dt;
    const Vec<D> x = x0 + v0 * t + 0.5 * t * t * g;
    const Vec<D> v_half = v0 + (t - 0.5 * dt) * g;  // velocity at t - dt/2
    const double scale = x0.norm() + v0.norm() * t + 0.5 * g.norm() * t * t;
    err_x = std::max(err_x, (w.particles.pos[0] - x).norm() / scale);
    err_v = std::max(err_v, (w.particles.vel[0] - v_half).norm() / (v0.norm() + g.norm() * t));
  }
  report(std::to_string(D) + "D free fall position (max over steps)", err_x);
  report(std::to_string(D) + "D free fall half-step velocity", err_v);
  EXPECT_LT(err_x, 1e-9);
  EXPECT_LT(err_v, 1e-9);
  EXPECT_NEAR(w.time, steps * dt, 1e-9 * steps * dt);
  EXPECT_EQ(w.step, static_cast<std::uint64_t>(steps));
  // No torque: no spin.
  EXPECT_EQ(Dim<D>::rot_norm2(w.particles.angvel[0]), 0.0);
}

TYPED_TEST(FreeFall, OnStepStartIsHalfAStepAhead) {
  constexpr int D = TypeParam::value;
  const Vec<D> g = vec<D>(0.0, -9.81, 0.0);
  const Vec<D> x0 = vec<D>(0.0, 10.0, 0.0), v0 = vec<D>(1.0, 0.0, 2.0);
  const double dt = 1e-3;
  const int steps = 1000;
  World<D> w = falling_grain<D>(x0, v0, g, dt);
  for (int k = 0; k < steps; ++k) step(w);
  const double t = steps * dt;
  const Vec<D> offset = w.particles.pos[0] - (x0 + v0 * t + 0.5 * t * t * g);
  EXPECT_LT((offset - 0.5 * dt * t * g).norm(), 1e-9 * (0.5 * dt * t * g).norm());
}

// A grain placed touching a floor, at rest, settles under local damping until the floor
// carries exactly its weight and the overlap is the static one.
TYPED_TEST(FreeFall, RestOnFloorLinear) {
  constexpr int D = TypeParam::value;
  const double kn = 1e5, r = 0.01, rho = 2600.0, g = 9.81;
  World<D> w;
  const auto mat = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 1.0, rho));
  add_plane(w, vec<D>(0.0, 0.0), vec<D>(0.0, 1.0), mat, "floor");
  w.resolve_pair_laws();
  w.gravity = vec<D>(0.0, -g);
  w.local_damping = 0.7;
  w.particles.add(vec<D>(0.0, r), r, rho, mat);
  const double m = mass(w, 0);
  w.dt = 0.05 * std::sqrt(m / kn);
  for (int k = 0; k < 20000; ++k) step(w);
  const double load = -w.walls[0].force.dot(w.walls[0].normal);
  const double weight = m * g;
  report(std::to_string(D) + "D grain at rest (linear): floor load vs weight",
         rel_err(load, weight));
  EXPECT_LT(rel_err(load, weight), 1e-6);
  EXPECT_LT(rel_err(overlap(w), weight / kn), 1e-6);
  EXPECT_LT(w.particles.vel[0].norm(), 1e-9 * g * std::sqrt(m / kn));
}

// The same with the Hertz law on a rigid floor: delta = (m g / (4/3 E* sqrt(R)))^(2/3).
TEST(FreeFall, RestOnFloorHertz) {
  const double r = 0.01, rho = 2600.0, g = 9.81, young = 1e8, nu = 0.3;
  World<3> w;
  const auto mat = add_material(w, hertz_material(young, nu, rho));
  const auto rigid = add_material(w, hertz_material(1e30, 0.3, rho, 0.0, 1.0, "rigid"));
  add_plane(w, vec<3>(0.0, 0.0), vec<3>(0.0, 1.0), rigid, "floor");
  w.resolve_pair_laws();
  w.gravity = vec<3>(0.0, -g);
  w.local_damping = 0.7;
  w.particles.add(vec<3>(0.0, r), r, rho, mat);
  const double m = mass(w, 0), weight = m * g;
  const double estar = young / (1.0 - nu * nu);
  const double delta = std::pow(weight / (4.0 / 3.0 * estar * std::sqrt(r)), 2.0 / 3.0);
  const double k_static = 2.0 * estar * std::sqrt(r * delta);  // dF/d(delta) at rest
  w.dt = 0.05 * std::sqrt(m / k_static);
  for (int k = 0; k < 20000; ++k) step(w);
  const double load = -w.walls[0].force.dot(w.walls[0].normal);
  report("3D grain at rest (Hertz): floor load vs weight", rel_err(load, weight));
  report("3D grain at rest (Hertz): overlap", rel_err(overlap(w), delta));
  EXPECT_LT(rel_err(load, weight), 1e-6);
  EXPECT_LT(rel_err(overlap(w), delta), 1e-6);
}

}  // namespace
}  // namespace geodem::test
