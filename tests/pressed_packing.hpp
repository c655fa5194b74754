// A packing that moves from its first step: grains of radius 1 mm on a lattice whose spacing
// is below their diameter, so that each starts pressed against its neighbours, in a box
// under gravity, with the automatic time step every 10 steps and renumbering every 3 list
// builds. With `extras`, rolling and twisting friction and weak bonds (a strength of
// kn x 5 um over the bond's section: many break). Shared by the tests that compare two runs
// bit for bit (thread count, checkpoints).
#pragma once

#include <random>

#include "contacts/bonds.hpp"
#include "test_util.hpp"

namespace geodem::test {

inline constexpr double kPackedRadius = 1e-3, kPackedDensity = 2600.0;

// n grains in a box `side` lattice spacings wide and height_ratio times as tall.
template <int D>
World<D> pressed_packing(bool extras, std::size_t n, int side, double height_ratio, unsigned seed) {
  constexpr double r = kPackedRadius, rho = kPackedDensity;
  World<D> w;
  const double kn = rho * Dim<D>::volume(r) * 9.81 / (1e-4 * r);
  Material gm = linear_material(kn, 0.5 * kn, 0.5, 0.3, rho);
  if (extras) {
    gm.rolling_friction = 0.2;
    gm.twisting_friction = 0.1;
    const double section = D == 2 ? 2.0 * r : 3.14159 * r * r;
    gm.normal_cohesion = gm.shear_cohesion = 5e-6 * kn / section;
  }
  const auto grain = add_material(w, gm);
  const auto wall = add_material(w, linear_material(kn, 0.5 * kn, 0.5, 0.3, rho, "wall"));
  const double spacing = 1.96 * r;
  Vec<D> hi = Vec<D>::Constant(side * spacing);
  hi[1] = height_ratio * side * spacing;
  add_box(w, Vec<D>(Vec<D>::Zero()), hi, wall, wall);
  w.resolve_pair_laws();
  std::mt19937_64 rng(seed);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), hi, spacing, 0.98 * r, r, 0.01 * r, 0.3, rho, grain, rng,
               n);
  if (extras) create_bonds(w, 0.0);
  w.gravity = vec<D>(0.0, -9.81, 0.0);
  // The automatic time step, every 10 steps: its stiffness sums are taken on slabs too.
  w.auto_dt = true;
  w.dt_safety = 0.3;
  w.dt_update_interval = 10;
  w.sort_interval = 3;
  return w;
}

}  // namespace geodem::test
