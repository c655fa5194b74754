// Energy conservation of an undamped, frictionless, elastic (e = 1) linear packing in a box
// of plane walls, with and without gravity, over 1e5 steps at dt = 0.01 sqrt(m_min/kn):
// a dense granular gas (random velocities, some 0.2 to 0.3 contacts per grain at any time).
//
// Kinetic energy on the step. The leapfrog holds v at half steps; the energy at step k uses
//   K_k = 1/2 sum m v(t_k - dt/2) . v(t_k + dt/2)   (+ the same for rotation),
// the velocities before and after step k. For forces linear in the positions (springs,
// gravity) the leapfrog conserves K_k + U(x_k) exactly, so what remains measures the
// engine. (The arithmetic mean of the two half-step kinetic energies instead carries the
// scheme's O((w dt)^2) phase oscillation; it is reported for comparison.)
// The elastic energy is the engine's own measure (ContactStats::elastic_energy, sum of
// kn delta^2/2 over grain-grain and grain-wall contacts), the gravity energy is
// gravity_energy() with the floor at height 0.
//
// Time step. The force has a kink where a contact opens or closes, which the leapfrog
// crosses within a step: each such event changes the energy by a random O((w dt)^2) part
// of the colliding pair's energy, and the events add up as a random walk. This packing
// drifts by 8e-4 at dt = 0.05 sqrt(m_min/kn), 1.1e-4 at half that step and 2e-5 at a
// quarter (same simulated time): the error converges with dt, it is no loss of energy.
// Neither the skin nor rebuilding the neighbour list every step changes it by one bit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class EnergyConservation : public ::testing::Test {};
TYPED_TEST_SUITE(EnergyConservation, Dims, DimNames);

struct EnergyRun {
  double max_drift = 0.0;       // max |E_k - E_0| / E_0, product kinetic energy
  double max_drift_mean = 0.0;  // same with the mean of the half-step kinetic energies
  double mean_contacts = 0.0;   // contacts per grain, mean over the measured steps
  double max_elastic_fraction = 0.0;
  double max_gravity_change = 0.0;  // max |U_g - U_g0| / E_0
  double max_kinetic = 0.0;         // max K / E_0
};

template <int D>
EnergyRun run_energy(bool gravity) {
  constexpr double r0 = 1e-3, rho = 2600.0, tau = 1e-4;
  const double m0 = rho * Dim<D>::volume(r0);
  const double kn = m0 / (tau * tau);
  World<D> w;
  const auto mat = add_material(w, linear_material(kn, 0.5 * kn, 0.0, 1.0, rho));
  const int per_side = D == 2 ? 20 : 7;
  const double spacing = 2.0 * r0;
  const double width = per_side * spacing;
  const double height = gravity ? 2.0 * width : width;
  const Vec<D> lo = Vec<D>::Zero();
  Vec<D> hi = Vec<D>::Constant(width);
  hi[1] = height;
  add_box(w, lo, hi, mat, mat);
  w.resolve_pair_laws();
  std::mt19937_64 rng(12345);
  Vec<D> fill_hi = hi;
  fill_hi[1] = width;
  // Radii in [0.8, 1] r0: no overlap at the start. Grains start from the lower cube.
  const std::size_t n =
      fill_lattice(w, lo, fill_hi, spacing, 0.8 * r0, r0, 0.0, 0.5, rho, mat, rng);
  EXPECT_EQ(n, static_cast<std::size_t>(std::pow(per_side, D)));
  // Strong enough for the column to collapse onto the floor within the run.
  if (gravity) w.gravity = vec<D>(0.0, -40.0, 0.0);
  const double m_min = rho * Dim<D>::volume(0.8 * r0);
  w.dt = 0.01 * std::sqrt(m_min / kn);

  auto& P = w.particles;
  std::vector<Vec<D>> v_before(n);
  std::vector<typename Dim<D>::Rot> w_before(n);
  EnergyRun run;
  double e0 = 0.0, ug0 = 0.0;
  const int steps = 100000, every = 50;
  for (int k = 0; k <= steps; ++k) {
    if (k % every != 0) {
      step(w);
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) v_before[i] = P.vel[i], w_before[i] = P.angvel[i];
    const double ug = gravity_energy(w);
    const double ke_before = kinetic_energy(w);
    w.measure_this_step = true;
    step(w);
    w.measure_this_step = false;
    double ke = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double m = 1.0 / P.inv_mass[i], inertia = 1.0 / P.inv_inertia[i];
      ke += 0.5 * m * v_before[i].dot(P.vel[i]);
      if constexpr (D == 2) {
        ke += 0.5 * inertia * w_before[i] * P.angvel[i];
      } else {
        ke += 0.5 * inertia * w_before[i].dot(P.angvel[i]);
      }
    }
    const double ke_mean = 0.5 * (ke_before + kinetic_energy(w));
    const double ue = w.stats.elastic_energy;
    const double e = ke + ue + ug, e_mean = ke_mean + ue + ug;
    if (k == 0) {
      e0 = e, ug0 = ug;
      continue;
    }
    run.max_drift = std::max(run.max_drift, std::abs(e - e0) / e0);
    run.max_drift_mean = std::max(run.max_drift_mean, std::abs(e_mean - e0) / e0);
    run.mean_contacts += static_cast<double>(w.stats.contacts + w.stats.wall_contacts) /
                         static_cast<double>(n) / (steps / every);
    run.max_elastic_fraction = std::max(run.max_elastic_fraction, ue / e0);
    run.max_gravity_change = std::max(run.max_gravity_change, std::abs(ug - ug0) / e0);
    run.max_kinetic = std::max(run.max_kinetic, ke / e0);
  }
  return run;
}

void check(const EnergyRun& r, const std::string& tag, bool gravity) {
  report(tag + " energy drift (product kinetic energy)", r.max_drift);
  report(tag + " energy drift (mean of half-step kinetic energies)", r.max_drift_mean);
  report(tag + " largest elastic energy fraction", r.max_elastic_fraction);
  EXPECT_LT(r.max_drift, 1e-4);
  // The packing does interact: many contacts, a sizeable elastic energy.
  report(tag + " mean contacts per grain", r.mean_contacts);
  EXPECT_GT(r.mean_contacts, 0.1);
  if (gravity) {
    report(tag + " largest change of gravity energy / E0", r.max_gravity_change);
    report(tag + " energy drift / largest kinetic energy", r.max_drift / r.max_kinetic);
    EXPECT_GT(r.max_gravity_change, 0.03);
    EXPECT_LT(r.max_drift / r.max_kinetic, 1e-3);
  }
  EXPECT_GT(r.max_elastic_fraction, 0.01);
}

TYPED_TEST(EnergyConservation, ElasticPackingNoGravity) {
  constexpr int D = TypeParam::value;
  check(run_energy<D>(false), std::to_string(D) + "D no gravity:", false);
}

TYPED_TEST(EnergyConservation, ElasticPackingWithGravity) {
  constexpr int D = TypeParam::value;
  check(run_energy<D>(true), std::to_string(D) + "D gravity:", true);
}

}  // namespace
}  // namespace geodem::test
