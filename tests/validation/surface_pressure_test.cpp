// The surcharge plate (controllers/surface_pressure.hpp): a plate lowered onto a column of
// grains in a smooth box, without gravity, settles at the requested pressure, and the
// floor carries the same force (equilibrium of the column).
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "controllers/surface_pressure.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class SurfacePressureTest : public ::testing::Test {};
TYPED_TEST_SUITE(SurfacePressureTest, Dims, DimNames);

TYPED_TEST(SurfacePressureTest, PlateHoldsItsPressure) {
  constexpr int D = TypeParam::value;
  World<D> w;
  const auto mat = add_material(w, modulus_material(1e7, 0.5, 0.3, 0.5));
  // Smooth walls: with friction, the side walls would carry part of the load (Janssen).
  const auto smooth = add_material(w, modulus_material(1e7, 0.5, 0.0, 0.5, 2600.0, "wall"));
  const double r = 0.005, width = 0.1;
  Vec<D> hi = Vec<D>::Constant(width);
  hi[1] = 0.3;
  add_box(w, Vec<D>(Vec<D>::Zero()), hi, smooth, smooth);
  // The top wall of the box (index 3, normal -y) is the plate.
  const double area = D == 2 ? width : width * width;
  w.walls[3].area = w.walls[2].area = area;
  w.walls[3].point[1] = 0.12;
  w.resolve_pair_laws();
  std::mt19937_64 rng(3);
  hi[1] = 0.11;
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), hi, 2.2 * r, 0.8 * r, r, 0.05 * r, 0.0, 2600.0, mat, rng);
  w.auto_dt = true;
  w.local_damping = 0.3;
  const double q = 2e4;
  update_timestep(w);
  auto plate = std::make_shared<SurfacePressure<D>>(3, q, 0.05 * r / w.dt);
  w.controllers = {plate};
  for (int k = 0; k < 15000; ++k) step(w);
  const double on_plate = plate->pressure(w), on_floor = w.walls[2].normal_stress();
  report(std::to_string(D) + "D surcharge plate: pressure error", rel_err(on_plate, q));
  report(std::to_string(D) + "D surcharge plate: floor stress error", rel_err(on_floor, q));
  EXPECT_LT(rel_err(on_plate, q), 1e-2);
  EXPECT_LT(rel_err(on_floor, q), 1e-2);
}

}  // namespace
}  // namespace geodem::test
