// A deposit of 2000 grains under gravity in a box of plane walls, settled with local
// damping, comes to rest and its floor carries its whole weight. The side walls are
// frictionless, so they take no vertical load (no Janssen effect): at rest the floor force
// equals the total weight up to the residual unbalanced forces.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "test_util.hpp"

namespace geodem::test {
namespace {

// Kinetic energy of the translations. A few spheres keep spinning about the normal of their
// contacts (a grain alone on the floor spinning about the vertical, one held between two
// grains spinning about the line joining them): that twist loads no tangential spring and
// the model has no twisting resistance, so nothing damps it. It is reported, but it does
// not count against rest.
template <int D>
double translational_energy(const World<D>& w) {
  double e = 0.0;
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    e += 0.5 * mass(w, i) * w.particles.vel[i].squaredNorm();
  return e;
}

template <typename T>
class Deposit : public ::testing::Test {};
TYPED_TEST_SUITE(Deposit, Dims, DimNames);

TYPED_TEST(Deposit, SettlesAndFloorCarriesTheWeight) {
  constexpr int D = TypeParam::value;
  constexpr double r0 = 1e-3, rho = 2600.0, g = 9.81;
  constexpr std::size_t n_grains = 2000;
  World<D> w;
  const double spacing = 2.1 * r0;
  const int across = D == 2 ? 40 : 12;  // grains along each horizontal axis
  // Contact modulus (kn = E r for equal grains in 3D, kn = E per metre in 2D) for an overlap
  // of ~5e-3 r0 under the weight of the column, whose height in grains is n / across^(D-1).
  const double layers = static_cast<double>(n_grains) / std::pow(across, D - 1);
  const double kn = rho * Dim<D>::volume(r0) * g * layers / (5e-3 * r0);
  const double young = D == 3 ? kn / r0 : kn;
  const auto grain = add_material(w, modulus_material(young, 0.5, 0.5, 0.5, rho));
  const auto floor = add_material(w, modulus_material(young, 0.5, 0.5, 0.5, rho, "floor"));
  const auto smooth = add_material(w, modulus_material(young, 0.5, 0.0, 0.5, rho, "smooth"));
  Vec<D> hi = Vec<D>::Constant(across * spacing);
  hi[1] = 1.0;  // tall enough for the loose lattice
  add_box(w, Vec<D>(Vec<D>::Zero()), hi, floor, smooth);
  w.resolve_pair_laws();
  std::mt19937_64 rng(2024);
  const std::size_t n = fill_lattice(w, Vec<D>(Vec<D>::Zero()), hi, spacing, 0.8 * r0, r0,
                                     0.04 * r0, 0.01, rho, grain, rng, n_grains);
  ASSERT_EQ(n, n_grains);
  w.gravity = vec<D>(0.0, -g, 0.0);
  w.local_damping = 0.7;
  w.auto_dt = true;

  const double weight = total_mass(w) * g;
  double ratio = 1.0, ke = 1.0;
  std::size_t steps = 0;
  const std::size_t max_steps = 200000, check_every = 500;
  const double ke_scale = weight * r0;  // the energy of lifting the deposit by one radius
  while (steps < max_steps) {
    for (std::size_t k = 0; k + 1 < check_every; ++k) step(w);
    w.measure_this_step = true;
    step(w);
    w.measure_this_step = false;
    steps += check_every;
    ratio = unbalanced_force_ratio(w);
    ke = translational_energy(w);
    if (ratio < 1e-4 && ke < 1e-8 * ke_scale) break;
  }
  const double load = -w.walls[2].force.dot(w.walls[2].normal);
  double side_vertical = 0.0;
  for (std::size_t k = 0; k < w.walls.size(); ++k)
    if (k != 2) side_vertical += std::abs(w.walls[k].force.y());
  const std::string tag = std::to_string(D) + "D deposit of " + std::to_string(n) + ": ";
  report(tag + "steps to rest", static_cast<double>(steps));
  report(tag + "unbalanced force ratio", ratio);
  report(tag + "translational kinetic energy / (weight x r0)", ke / ke_scale);
  report(tag + "kinetic energy with rotations / (weight x r0)", kinetic_energy(w) / ke_scale);
  report(tag + "floor load vs weight", rel_err(load, weight));
  report(tag + "coordination number", coordination_number(w));
  EXPECT_LT(ratio, 1e-3);
  EXPECT_LT(ke, 1e-8 * ke_scale);
  EXPECT_LT(rel_err(load, weight), 0.005);
  EXPECT_LT(side_vertical, 1e-12 * weight);  // frictionless sides: no vertical load
  // The deposit is a packing, not a gas: every grain is held by contacts.
  EXPECT_GT(coordination_number(w), D == 2 ? 3.0 : 4.0);
  // Everything lies in the box.
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_GT(w.particles.pos[i].y(), 0.0);
    ASSERT_LT(w.particles.pos[i].y(), 0.3);
  }
}

}  // namespace
}  // namespace geodem::test
