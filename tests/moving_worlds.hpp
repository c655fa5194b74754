// Worlds in motion shared by the tests that compare two runs bit for bit (thread count,
// contact paths): a sheared periodic cell of colliding grains and a crowd of three-grain
// clumps thrown together, and the comparison of arrays and grains by their bytes.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <vector>

#include "clumps/clump_template.hpp"
#include "contacts/contact_batch.hpp"
#include "test_util.hpp"

namespace geodem::test {

// Puts the step back on its default contact path when a test that chose one ends.
struct ContactPathGuard {
  ~ContactPathGuard() { set_contact_path(default_contact_path()); }
};

// Whether two arrays hold the same bytes.
template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The grains' state, their numbering and the listed pairs with their springs.
template <int D>
void expect_same_grains(const World<D>& a, const World<D>& b) {
  EXPECT_TRUE(same_bits(a.particles.pos, b.particles.pos));
  EXPECT_TRUE(same_bits(a.particles.vel, b.particles.vel));
  EXPECT_TRUE(same_bits(a.particles.angvel, b.particles.angvel));
  EXPECT_TRUE(same_bits(a.particles.id, b.particles.id));
  EXPECT_TRUE(same_bits(a.nlist.other, b.nlist.other));
  EXPECT_TRUE(same_bits(a.nlist.spring, b.nlist.spring));
}

// A periodic cell `side` lattice spacings wide, sheared at 20 /s, of grains (radii 0.8 to 1
// mm) given random velocities up to 2 m/s: they collide through the faces from the start.
template <int D>
World<D> sheared_cell(int side) {
  const double r = 1e-3, spacing = 2.1e-3, kn = D == 2 ? 1e6 : 1e4;
  const Vec<D> size = Vec<D>::Constant(side * spacing);
  World<D> w;
  add_material(w, linear_material(kn, 0.5 * kn, 0.5, 0.7, 2600.0));
  w.resolve_pair_laws();
  w.cell.periodic = true;
  w.cell.h = size.asDiagonal();
  w.cell.vel_grad(0, 1) = 20.0;
  w.sort_interval = 2;
  std::mt19937_64 rng(5);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), size, spacing, 0.8 * r, r, 0.04 * r, 2.0, 2600.0, 0, rng);
  w.dt = 1e-6;
  return w;
}

// Three-grain clumps (the sums over a clump's members then depend on their order) on a
// counts[0] x counts[1] (x counts[2]) lattice, created in an order unrelated to the cells so
// that the first build renumbers them, thrown towards the centre (throw_clumps_together).
template <int D>
World<D> colliding_clumps(std::array<int, 3> counts, double restitution) {
  World<D> w;
  const auto mat = add_material(w, modulus_material(1e7, 0.5, 0.5, restitution));
  w.resolve_pair_laws();
  ClumpTemplate<D> shape;
  shape.centre = {Vec<D>::Zero(), Vec<D>(1.8 * axis<D>(0)),
                  Vec<D>(0.9 * axis<D>(0) + 1.4 * axis<D>(1))};
  shape.radius = {1.0, 1.0, 0.8};
  std::mt19937_64 rng(9);
  throw_clumps_together(w, resolve_clump(shape), counts, 0.05, 0.0005, 30.0, mat, rng);
  w.local_damping = 0.2;
  w.dt = 1e-5;
  w.sort_interval = 2;
  return w;
}

}  // namespace geodem::test
