// The interface shear box (lab/interface_box.hpp, controllers/plate_servo.hpp) against
// closed forms:
// - a row of grains that cannot roll, pressed by the plate on the sheet and held by the
//   far side wall while the sheet slides under them: every grain-sheet contact slides,
//   so the shear stress on the sheet over its normal stress is exactly tan(delta)
//   (tolerance 1e-3 relative), whatever the normal stress;
// - the plate servo holds its target within 1 % while the sheet slides.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "controllers/plate_servo.hpp"
#include "lab/interface_box.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

struct SlidingRow {
  double ratio = 0.0;        // mean tau / sigma_n on the sheet while sliding
  double servo_error = 0.0;  // largest |plate pressure / target - 1| over the sliding
  double slip = 0.0;         // sheet travel (m)
};

SlidingRow slide_row(double delta_deg, double sigma_n) {
  World<2> w;
  const auto soil = add_material(w, modulus_material(5e7, 0.5, 0.5, 1.0));
  add_material(w, modulus_material(5e7, 0.5, 0.0, 1.0, 2600.0, "walls"));
  add_material(w, modulus_material(5e7, 0.5, 0.0, 1.0, 2600.0, "sheet"));
  const double r = 0.005;
  InterfaceBox b;
  b.length = 20.5 * r;  // ten grains side by side, a little play
  b.thickness = 0.001;
  b.element_length = 1.7 * r;
  b.travel = 0.02;
  b.margin = 4.0 * r;
  add_interface_box_walls(w, b);
  add_rigid_base_sheet(w, b);
  w.resolve_pair_laws();
  const double mu = std::tan(delta_deg * std::numbers::pi / 180.0);
  w.pair_laws[0 * 3 + 2].mu = w.pair_laws[2 * 3 + 0].mu = mu;
  w.update_contact_extras();
  for (int k = 0; k < 10; ++k) {
    const auto i = w.particles.add(Dim<2>::Vec((2 * k + 1) * r, b.thickness + r), r, 2600.0, soil);
    w.particles.inv_inertia[i] = 0.0;  // grains that cannot roll
  }
  const std::size_t plate = add_loading_plate(w, b, b.thickness + 2.0 * r + 0.05 * r);
  w.auto_dt = true;
  w.local_damping = 0.3;
  update_timestep(w);
  auto servo = std::make_shared<PlateServo<2>>(plate, sigma_n, 0.05 * r / w.dt);
  w.controllers = {servo};
  for (int k = 0; k < 20000; ++k) step(w);

  drive_sheet(w, 0.02);
  const double x0 = w.spars.pos[0].x();
  SlidingRow out;
  double tau = 0.0, sig = 0.0;
  for (int k = 0; k < 40000; ++k) {
    step(w);
    if (k < 10000) continue;  // the row is carried to the far wall first
    const InterfaceStresses s = interface_stresses(w, b.length);
    tau += s.shear, sig += s.normal;
    out.servo_error = std::max(out.servo_error, std::abs(servo->pressure(w) / sigma_n - 1.0));
  }
  out.ratio = tau / sig;
  out.slip = w.spars.pos[0].x() - x0;
  return out;
}

TEST(InterfaceShear, GrainsThatCannotRollSlideAtTheLocalFriction) {
  for (double delta : {15.0, 34.0, 45.0})
    for (double sigma : {1e4, 1e5}) {
      const SlidingRow s = slide_row(delta, sigma);
      const double want = std::tan(delta * std::numbers::pi / 180.0);
      report("interface shear, delta " + std::to_string(static_cast<int>(delta)) + " deg, " +
                 std::to_string(static_cast<int>(sigma / 1e3)) + " kPa: tau/sigma error",
             rel_err(s.ratio, want));
      report("  plate servo: largest relative error while sliding", s.servo_error);
      EXPECT_GT(s.slip, 0.01);
      EXPECT_LT(rel_err(s.ratio, want), 1e-3);
      EXPECT_LT(s.servo_error, 1e-2);
    }
}

}  // namespace
}  // namespace geodem::test
