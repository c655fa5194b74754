// The stress servo (controllers/stress_servo.hpp): one step is the closed form of its
// proportional-integral law, the two walls of an axis always move by the same amount in
// opposite directions, and in closed loop on a pressed packing it brings the stresses to
// the target without moving the box's centre: a sample the servo drove as a rigid body
// would defeat local damping and never come to rest.
#include <gtest/gtest.h>

#include <cmath>

#include <random>
#include "controllers/stress_servo.hpp"
#include "measure/measurements.hpp"

#include "test_util.hpp"

namespace geodem::test {
namespace {

// Walls of unequal stiffness: the law uses their mean, and both walls get the same speed.
TEST(StressServo, OneStepIsTheClosedForm) {
  World<2> w;
  w.materials = {linear_material(1e6, 5e5, 0.5, 0.3, 2600.0)};
  const LabBox<2> box = LabBox<2>::add_to(w, Vec<2>(0.0, 0.0), Vec<2>(1.0, 2.0), 0);
  w.dt = 1e-2;
  auto& lo = w.walls[box.lo[0]];
  auto& hi = w.walls[box.hi[0]];
  lo.stiffness = 1e6;
  hi.stiffness = 3e6;
  lo.force = -1500.0 * lo.normal;  // 1500 and 2500 N on a face of 2 m: mean 1000 Pa
  hi.force = -2500.0 * hi.normal;
  const double gain = 0.5, integral_gain = 0.1, target = 600.0;
  StressServo<2> servo(box, 0, target, gain, integral_gain);
  double sum = 0.0;
  for (int k = 1; k <= 3; ++k) {
    servo.apply(w);
    const double e = (1000.0 - target) * 2.0 / 2e6;  // displacement error of the mean stiffness
    sum += e;
    const double v = (gain * e + integral_gain * sum) / w.dt;  // outward, 0.032 m/s at k = 3
    EXPECT_NEAR(lo.velocity[0], -v, 1e-12 * v) << "step " << k;
    EXPECT_EQ(hi.velocity[0], -lo.velocity[0]);
    EXPECT_EQ(lo.velocity[1], 0.0);
    EXPECT_EQ(hi.velocity[1], 0.0);
  }
  // Near the speed cap (max_strain_rate x size, 1 m/s here) the sum stops growing: the
  // speed stays within one integral increment below the cap.
  for (int k = 0; k < 1000; ++k) servo.apply(w);
  const double held = lo.velocity[0];
  for (int k = 0; k < 1000; ++k) servo.apply(w);
  EXPECT_EQ(lo.velocity[0], held);
  EXPECT_LE(-held, 1.0);
  EXPECT_GT(-held, 1.0 - integral_gain * 4e-4 / w.dt);
  EXPECT_EQ(hi.velocity[0], -held);
}

// Grains at rest on a square (cubic) lattice 1.9 r apart, radii in [0.96 r, r]: they press on
// their neighbours and on the walls. The hi walls' material is three times as stiff as the lo
// walls': their contact stiffnesses differ.
// Nearly elastic contacts: a dashpot's force at the walls' speed would be more than the
// elastic stresses of so small a box.
template <int D>
World<D> pressed_lattice() {
  constexpr double r = 1e-3;
  World<D> w;
  const double kn = 1e5;
  const auto grain = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 0.95));
  const auto wall = add_material(w, linear_material(kn, 0.5 * kn, 0.0, 0.95, 2600.0, "wall"));
  const auto stiff =
      add_material(w, linear_material(3.0 * kn, 1.5 * kn, 0.0, 0.95, 2600.0, "stiff wall"));
  const double spacing = 1.9 * r;
  const Vec<D> hi = Vec<D>::Constant((D == 2 ? 12 : 6) * spacing);
  add_box(w, Vec<D>(Vec<D>::Zero()), hi, wall, wall);
  for (int k = 0; k < D; ++k) w.walls[2 * k + 1].material = stiff;
  w.resolve_pair_laws();
  std::mt19937_64 rng(11);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), hi, spacing, 0.96 * r, r, 0.005 * r, 0.0, 2600.0, grain,
               rng);
  w.auto_dt = true;
  w.dt_safety = 0.3;
  w.local_damping = 0.3;
  return w;
}

template <typename T>
class StressServoLoop : public ::testing::Test {};
TYPED_TEST_SUITE(StressServoLoop, Dims, DimNames);

// Servos on every axis unload the pressed lattice to half its stress.
TYPED_TEST(StressServoLoop, ReachesTheTargetWithTheBoxCentreFixed) {
  constexpr int D = TypeParam::value;
  World<D> w = pressed_lattice<D>();
  LabBox<D> box;  // add_box's walls: lo0, hi0, lo1, hi1 (, lo2, hi2)
  for (int k = 0; k < D; ++k) box.lo[k] = 2 * k, box.hi[k] = 2 * k + 1;
  step(w);
  const double target = 0.5 * box.mean_stress(w);
  ASSERT_GT(target, 0.0);
  for (int k = 0; k < D; ++k)
    w.controllers.push_back(std::make_shared<StressServo<D>>(box, k, target, 0.5, 0.1, 10.0));
  auto centre = [&](int k) {
    return 0.5 * (w.walls[box.lo[k]].point[k] + w.walls[box.hi[k]].point[k]);
  };
  Vec<D> c0;
  for (int k = 0; k < D; ++k) c0[k] = centre(k);
  const double size = box.size(w)[0];
  double lo_stiff = 0.0, hi_stiff = 0.0;  // summed over the run
  for (int s = 1; s <= 3000; ++s) {
    w.measure_this_step = s % 100 == 0;
    step(w);
    lo_stiff += w.walls[box.lo[0]].stiffness;
    hi_stiff += w.walls[box.hi[0]].stiffness;
  }
  EXPECT_GT(std::abs(hi_stiff / lo_stiff - 1.0), 0.1);  // 0.75 in 2D
  for (int k = 0; k < D; ++k) {
    report(std::to_string(D) + "D servo loop: sigma_" + std::to_string(k) + " / target - 1",
           box.stress(w, k) / target - 1.0);
    EXPECT_NEAR(box.stress(w, k), target, 0.01 * target) << "axis " << k;
    // The walls' positions change by +-v dt each step: the centre moves by rounding only.
    EXPECT_NEAR(centre(k), c0[k], 1e-12 * size) << "axis " << k;
  }
  EXPECT_LT(unbalanced_force_ratio(w), 0.01);
}

}  // namespace
}  // namespace geodem::test
