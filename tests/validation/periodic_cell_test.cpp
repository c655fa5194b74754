// The periodic cell (world/periodic_cell.hpp) against closed forms and conservation laws:
// - a touching lattice strained affinely carries the stress kn eps_k (1 - eps_k) /
//   (a prod(1 - eps_m)) on each axis (1e-9);
// - a pair of grains in contact sliding across the cell's faces, its partner seen through
//   the boundary and wrapped back at every rebuild, has the forces of the same pair in the
//   middle of the cell (1e-9 relative): the contact keeps its history across the boundary;
// - a dense gas colliding through the faces conserves momentum (1e-12 relative);
// - the cell's sum of d f^T is the per-contact sum of a measured step (1e-12);
// - a simple-shear velocity gradient carries grains without contacts on the imposed
//   homogeneous profile, x(t) = x0 + gamma_dot y0 t (1e-12), and tilts the cell;
// - the cell servo holds an isotropic stress target, then the lateral stresses of a
//   strain-controlled compression, within 1 %.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "broadphase/neighbour_search.hpp"
#include "contacts/contact_forces.hpp"
#include "controllers/cell_servo.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class PeriodicCellTest : public ::testing::Test {};
TYPED_TEST_SUITE(PeriodicCellTest, Dims, DimNames);

constexpr double kR = 1e-3, kRho = 2600.0;

template <int D>
World<D> periodic_world(const Vec<D>& size, const Material& m) {
  World<D> w;
  add_material(w, m);
  w.resolve_pair_laws();
  w.cell.periodic = true;
  w.cell.h = size.asDiagonal();
  return w;
}

TYPED_TEST(PeriodicCellTest, StrainedLatticeGivesTheClosedFormStress) {
  constexpr int D = TypeParam::value;
  const double a = 2.0 * kR, kn = 1e4;
  const int n = 6;
  World<D> w = periodic_world<D>(Vec<D>::Constant(n * a), linear_material(kn, 0.5 * kn, 0.5, 1.0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < (D == 3 ? n : 1); ++k)
        w.particles.add(vec<D>(i + 0.5, j + 0.5, k + 0.5) * a, kR, kRho, 0);
  const Vec<D> eps = vec<D>(1e-3, 2e-3, 0.5e-3);
  typename Dim<D>::Tensor F = (Vec<D>::Ones() - eps).asDiagonal();
  w.cell.h = F * w.cell.h;
  for (auto& x : w.particles.pos) x = F * x;
  w.dt = 1e-6;
  build_neighbour_list(w);
  compute_contact_forces(w);
  const auto sigma = cell_stress(w);
  double prod = 1.0;
  for (int k = 0; k < D; ++k) prod *= 1.0 - eps[k];
  // Every grain has one +k neighbour, a (1 - eps_k) away with overlap a eps_k: N contacts of
  // force kn a eps_k and branch a (1 - eps_k) each, over the volume N a^D prod(1 - eps).
  for (int k = 0; k < D; ++k) {
    const double want = kn * eps[k] * (1.0 - eps[k]) / (std::pow(a, D - 2) * prod);
    report(std::to_string(D) + "D lattice: stress error, axis " + std::to_string(k),
           rel_err(sigma(k, k), want));
    EXPECT_LT(rel_err(sigma(k, k), want), 1e-9);
  }
  EXPECT_LT(std::abs(sigma(0, 1)), 1e-9 * std::abs(sigma(0, 0)));
  // The listed pairs that cross the faces carry images; every grain has 2D neighbours.
  std::size_t crossing = 0;
  for (const auto& im : w.nlist.image) crossing += !im.home();
  EXPECT_GT(crossing, 0u);
  EXPECT_EQ(w.nlist.other.size(), static_cast<std::size_t>(D * std::pow(n, D)));
}

// Two grains overlapping by a tenth of a radius, moved at given velocities (fixed grains:
// the kinematics is imposed, the forces are only computed): they translate together and
// slide past each other, so that the tangential spring loads to Coulomb's limit and slips.
// `offset` places the pair (grain 0 at `offset`).
template <int D>
World<D> sliding_pair(const Vec<D>& offset) {
  World<D> w =
      periodic_world<D>(Vec<D>::Constant(12 * kR), linear_material(1e4, 5e3, 0.5, 0.5, kRho));
  const Vec<D> drift = vec<D>(0.6, 0.25, 0.1);
  w.particles.add(offset, kR, kRho, 0, Vec<D>(drift + vec<D>(0.0, 0.02, 0.0)));
  w.particles.add(Vec<D>(offset + vec<D>(1.9 * kR, 0.0, 0.0)), kR, kRho, 0,
                  Vec<D>(drift - vec<D>(0.0, 0.02, 0.0)));
  for (auto& f : w.particles.flags) f |= kFixed;
  w.dt = 2e-6;
  return w;
}

TYPED_TEST(PeriodicCellTest, ContactAcrossTheBoundaryKeepsItsHistory) {
  constexpr int D = TypeParam::value;
  // The crossing pair starts near the +x face: grain 1 leaves through it at once, grain 0
  // after it, and the pair drifts across the y (and z) faces later.
  World<D> crossing = sliding_pair<D>(vec<D>(9.5 * kR, 10.5 * kR, 11.2 * kR));
  World<D> inside = sliding_pair<D>(vec<D>(3.0 * kR, 3.0 * kR, 3.0 * kR));
  double worst = 0.0, fmax = 0.0;
  std::size_t across = 0;
  for (int s = 0; s < 3000; ++s) {
    crossing.rebuild_needed = true;  // wrap and search through the faces every step
    step(crossing);
    step(inside);
    for (std::size_t g = 0; g < 2; ++g) {
      fmax = std::max(fmax, inside.particles.force[g].norm());
      worst = std::max(worst, (crossing.particles.force[g] - inside.particles.force[g]).norm());
    }
    across += !crossing.nlist.image.empty() && !crossing.nlist.image[0].home();
  }
  report(std::to_string(D) + "D pair across the faces: force difference / largest force",
         worst / fmax);
  EXPECT_GT(across, 100u);  // the contact was seen through the boundary
  EXPECT_GT(fmax, 0.0);
  EXPECT_LT(worst, 1e-9 * fmax);
  // The spring carried the friction all along (the pair was sheared, not apart).
  EXPECT_GT(spring_norm2<D>(crossing.nlist.spring[0]), 0.0);
}

TYPED_TEST(PeriodicCellTest, CollisionsThroughTheFacesConserveMomentum) {
  constexpr int D = TypeParam::value;
  const Vec<D> size = Vec<D>::Constant(D == 2 ? 40 * kR : 16 * kR);
  const double kn = D == 2 ? 1e6 : 1e4;  // 2D: per metre of thickness
  World<D> w = periodic_world<D>(size, linear_material(kn, 0.5 * kn, 0.5, 0.7, kRho));
  std::mt19937_64 rng(3);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), size, 2.4 * kR, 0.8 * kR, kR, 0.1 * kR, 1.0, kRho, 0,
               rng);
  w.dt = 1e-6;
  auto momentum = [&] {
    Vec<D> p = Vec<D>::Zero();
    for (std::size_t i = 0; i < w.particles.size(); ++i)
      p += w.particles.vel[i] / w.particles.inv_mass[i];
    return p;
  };
  double scale = 0.0;
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    scale += w.particles.vel[i].norm() / w.particles.inv_mass[i];
  const Vec<D> p0 = momentum();
  std::size_t crossing_contacts = 0;  // touching pairs seen through the faces, over the steps
  const auto& P = w.particles;
  for (int s = 0; s < 3000; ++s) {
    step(w);
    for (std::size_t i = 0; i < P.size(); ++i)
      for (std::uint32_t k = w.nlist.start[i]; k < w.nlist.start[i + 1]; ++k) {
        const std::uint32_t j = w.nlist.other[k];
        crossing_contacts +=
            !w.nlist.image[k].home() && w.branch(i, j, k).norm() < P.radius[i] + P.radius[j];
      }
  }
  const double drift = (momentum() - p0).norm() / scale;
  report(std::to_string(D) + "D gas through the faces: momentum drift / sum |p|", drift);
  EXPECT_LT(drift, 1e-12);
  EXPECT_GT(crossing_contacts, 100u);
}

// The cell's sum of d f^T (3D: summed over grains as x F^T plus the image offsets' part) is
// the sum over contacts that a measured step takes pair by pair, in a sheared cell where
// grains collide through the faces: the same to rounding (1e-12 of sum |f| times the
// largest branch).
TYPED_TEST(PeriodicCellTest, CellFabricIsTheSumOverContacts) {
  constexpr int D = TypeParam::value;
  const Vec<D> size = Vec<D>::Constant(D == 2 ? 40 * kR : 16 * kR);
  const double kn = D == 2 ? 1e6 : 1e4;
  World<D> w = periodic_world<D>(size, linear_material(kn, 0.5 * kn, 0.5, 0.7, kRho));
  std::mt19937_64 rng(9);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), size, 2.1 * kR, 0.8 * kR, kR, 0.1 * kR, 1.0, kRho, 0,
               rng);
  w.cell.vel_grad(0, 1) = 20.0;
  w.dt = 1e-6;
  w.measure_this_step = true;
  double worst = 0.0;
  std::size_t imaged_contacts = 0;
  for (int s = 0; s < 2000; ++s) {
    step(w);
    const double scale = w.stats.sum_force * 2.0 * kR;
    if (scale > 0.0)
      worst =
          std::max(worst, (w.cell_fabric - w.stats.fabric_stress).cwiseAbs().maxCoeff() / scale);
    for (std::size_t i = 0; i < w.particles.size(); ++i)
      for (std::uint32_t k = w.nlist.start[i]; k < w.nlist.start[i + 1]; ++k)
        imaged_contacts += !w.nlist.image[k].home() &&
                           w.branch(i, w.nlist.other[k], k).norm() <
                               w.particles.radius[i] + w.particles.radius[w.nlist.other[k]];
  }
  report(std::to_string(D) + "D cell fabric: difference from the sum over contacts", worst);
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(imaged_contacts, 100u);
}

TYPED_TEST(PeriodicCellTest, SimpleShearCarriesGrainsOnTheImposedProfile) {
  constexpr int D = TypeParam::value;
  const Vec<D> size = Vec<D>::Constant(30 * kR);
  World<D> w = periodic_world<D>(size, linear_material(1e4, 5e3, 0.5, 0.7, kRho));
  std::mt19937_64 rng(5);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), size, 6.0 * kR, 0.5 * kR, kR, kR, 0.0, kRho, 0, rng);
  const double rate = 50.0;  // 1/s: v_x = rate y
  w.cell.vel_grad(0, 1) = rate;
  w.dt = 1e-5;
  const auto x0 = w.particles.pos;
  const int steps = 400;
  for (int s = 0; s < steps; ++s) step(w);
  const double t = steps * w.dt;
  double worst = 0.0;
  for (std::size_t i = 0; i < w.particles.size(); ++i) {
    // The grain, or its image across the faces, is where the field carried it.
    Vec<D> want = x0[i];
    want[0] += rate * x0[i][1] * t;
    Vec<D> diff = w.particles.pos[i] - want;
    const Vec<D> frac = w.cell.h.inverse() * diff;
    diff -= w.cell.h * frac.array().round().matrix();
    worst = std::max(worst, diff.norm());
    EXPECT_EQ(w.particles.vel[i], Vec<D>::Zero());  // no fluctuation
  }
  report(std::to_string(D) + "D simple shear: distance from the affine profile / cell size",
         worst / size[0]);
  EXPECT_LT(worst, 1e-12 * size[0]);
  // The cell tilted by the shear strain.
  EXPECT_NEAR(w.cell.h(0, 1) / w.cell.h(1, 1), rate * t, 1e-12);
  EXPECT_GT(w.nlist.builds, 1u);  // the search wrapped grains in the tilted cell
}

TYPED_TEST(PeriodicCellTest, ServoHoldsTheStressTarget) {
  constexpr int D = TypeParam::value;
  const Vec<D> size = Vec<D>::Constant(D == 2 ? 60 * kR : 16 * kR);  // 841 discs, 343 spheres
  const double kn = 2e4;
  World<D> w = periodic_world<D>(size, linear_material(kn, 0.5 * kn, 0.4, 0.3, kRho));
  std::mt19937_64 rng(11);
  fill_lattice(w, Vec<D>(Vec<D>::Zero()), size, 2.0 * kR, 0.9 * kR, kR, 0.02 * kR, 0.0, kRho, 0,
               rng);
  w.local_damping = 0.3;
  w.dt = 0.2 * std::sqrt(kRho * Dim<D>::volume(0.7 * kR) / kn);
  // Target: overlaps of about 1e-3 of a radius.
  const double target = kn * 1e-3 * kR / std::pow(2.0 * kR, D - 1);
  using Axis = typename CellServo<D>::Axis;
  std::array<Axis, D> iso;
  for (auto& a : iso) a = Axis{true, target, 0.0};
  const double max_rate = 2.0;
  auto servo = std::make_shared<CellServo<D>>(iso, max_rate, 0.1);
  w.controllers.push_back(servo);
  // The largest relative error of the first `axes` stresses over the next steps.
  auto worst_error = [&](int steps, int axes) {
    double worst = 0.0;
    for (int s = 0; s < steps; ++s) {
      step(w);
      const auto sigma = cell_stress(w);
      for (int k = 0; k < axes; ++k) worst = std::max(worst, std::abs(sigma(k, k) / target - 1.0));
    }
    return worst;
  };
  worst_error(40000, D);  // compression to the target
  const double hold = worst_error(2000, D);
  report(std::to_string(D) + "D cell servo: isotropic stress error", hold);
  EXPECT_LT(hold, 0.01);
  // Compression at a constant rate along the last axis, the others held at the target.
  const double rate = 0.005;  // 1/s: inertial number about 1e-4
  Axis axial{false, 0.0, -rate};
  servo->set_axis(D - 1, axial);
  const double h0 = w.cell.h(D - 1, D - 1);
  worst_error(2000, D - 1);  // the change of loading
  const double lateral = worst_error(8000, D - 1);
  report(std::to_string(D) + "D cell servo: lateral stress error in compression", lateral);
  EXPECT_LT(lateral, 0.01);
  EXPECT_LT(w.cell.h(D - 1, D - 1), h0 * (1.0 - 0.8 * rate * 10000 * w.dt));  // compressed
  EXPECT_GT(cell_stress(w)(D - 1, D - 1), 1.05 * target);
}

}  // namespace
}  // namespace geodem::test
