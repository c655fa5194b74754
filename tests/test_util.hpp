// Shared helpers of the test suite: dimension-generic construction of worlds,
// materials, walls and grain clouds, and the measurement of a single collision.
// Conventions of the tests: the vertical axis is y (index 1) in 2D and in 3D, so
// one body of code serves discs and spheres; motion in the x-y plane spins about z.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <type_traits>

#include "base/dim.hpp"
#include "clumps/clump_dynamics.hpp"
#include "clumps/clump_template.hpp"
#include "materials/material.hpp"
#include "measure/measurements.hpp"
#include "world/step.hpp"
#include "world/world.hpp"

namespace geodem::test {

// The dimensions every typed test runs in.
template <int D>
using DimC = std::integral_constant<int, D>;
using Dims = ::testing::Types<DimC<2>, DimC<3>>;

// Names the typed instances "2D" and "3D" instead of "0" and "1".
struct DimNames {
  template <typename T>
  static std::string GetName(int) {
    return std::to_string(T::value) + "D";
  }
};

template <int D>
using Vec = typename Dim<D>::Vec;

// A folder of this test's own under the test temp dir: the process id and the test's
// full name keep test processes that CTest runs side by side out of each other's files.
inline std::string unique_temp_dir(const std::string& tag) {
  std::string name = tag + "_" + std::to_string(::getpid());
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info())
    name += std::string("_") + info->test_suite_name() + "_" + info->name();
  for (char& c : name)
    if (c == '/') c = '_';
  return ::testing::TempDir() + "/geodem_" + name;
}

// A vector from its x, y (and z in 3D) components.
template <int D>
Vec<D> vec(double x, double y, double z = 0.0) {
  Vec<D> v;
  v[0] = x;
  v[1] = y;
  if constexpr (D == 3) v[2] = z;
  return v;
}

// Unit vector along one axis.
template <int D>
Vec<D> axis(int k) {
  Vec<D> v = Vec<D>::Zero();
  v[k] = 1.0;
  return v;
}

// Angular velocity about z (the only one in 2D).
template <int D>
double spin_z(const typename Dim<D>::Rot& w) {
  if constexpr (D == 2) {
    return w;
  } else {
    return w.z();
  }
}

inline double rel_err(double got, double want) {
  return std::abs(got - want) / std::abs(want);
}

// Prints one measured quantity so that a run of the suite documents its accuracy.
inline void report(const std::string& what, double value) {
  std::printf("[ measured ] %-58s %.3e\n", what.c_str(), value);
}

// Linear spring-dashpot material with constant stiffnesses.
inline Material linear_material(double kn, double kt, double friction, double restitution,
                                double density = 2600.0, const std::string& name = "grain") {
  Material m;
  m.name = name;
  m.law = LawKind::kLinear;
  m.density = density;
  m.kn = kn;
  m.kt = kt;
  m.friction = friction;
  m.restitution = restitution;
  return m;
}

// Linear material whose stiffness follows from a contact modulus: kn = 2 E r1 r2 / (r1 + r2).
inline Material modulus_material(double young, double kt_over_kn, double friction,
                                 double restitution, double density = 2600.0,
                                 const std::string& name = "grain") {
  Material m;
  m.name = name;
  m.law = LawKind::kLinear;
  m.density = density;
  m.young = young;
  m.kt_over_kn = kt_over_kn;
  m.friction = friction;
  m.restitution = restitution;
  return m;
}

inline Material hertz_material(double young, double poisson, double density, double friction = 0.0,
                               double restitution = 1.0, const std::string& name = "grain") {
  Material m;
  m.name = name;
  m.law = LawKind::kHertz;
  m.density = density;
  m.young = young;
  m.poisson = poisson;
  m.friction = friction;
  m.restitution = restitution;
  return m;
}

template <int D>
std::uint16_t add_material(World<D>& w, const Material& m) {
  w.materials.push_back(m);
  return static_cast<std::uint16_t>(w.materials.size() - 1);
}

// Adds an infinite plane through `point`; `normal` (normalised here) points to the grains.
template <int D>
std::size_t add_plane(World<D>& w, const Vec<D>& point, const Vec<D>& normal, std::uint16_t mat,
                      const std::string& name = "plane") {
  Wall<D> wall;
  wall.name = name;
  wall.kind = WallKind::kPlane;
  wall.point = point;
  wall.normal = normal.normalized();
  wall.material = mat;
  w.walls.push_back(wall);
  return w.walls.size() - 1;
}

// Encloses [lo, hi] by 2 D planes: wall 2k is the face lo[k] (normal +e_k), wall 2k+1 the
// face hi[k]. The floor (wall 2, y = lo[1]) gets `floor_mat`, every other face `side_mat`.
template <int D>
void add_box(World<D>& w, const Vec<D>& lo, const Vec<D>& hi, std::uint16_t floor_mat,
             std::uint16_t side_mat) {
  for (int k = 0; k < D; ++k) {
    add_plane(w, lo, axis<D>(k), k == 1 ? floor_mat : side_mat, "lo" + std::to_string(k));
    add_plane(w, hi, Vec<D>(-axis<D>(k)), side_mat, "hi" + std::to_string(k));
  }
}

template <int D>
double mass(const World<D>& w, std::size_t i) {
  return 1.0 / w.particles.inv_mass[i];
}

template <int D>
double total_mass(const World<D>& w) {
  double m = 0.0;
  for (std::size_t i = 0; i < w.particles.size(); ++i) m += mass(w, i);
  return m;
}

// Fills [lo, hi] with grains on a jittered square (cubic) lattice of the given spacing,
// bottom row first, until `max_n` grains. Radii uniform in [rmin, rmax], each velocity
// component uniform in [-vmax, vmax]. The jitter keeps every pair apart when
// 2 rmax + 2 jitter <= spacing.
template <int D>
std::size_t fill_lattice(World<D>& w, const Vec<D>& lo, const Vec<D>& hi, double spacing,
                         double rmin, double rmax, double jitter, double vmax, double density,
                         std::uint16_t mat, std::mt19937_64& rng,
                         std::size_t max_n = std::numeric_limits<std::size_t>::max()) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::array<int, 3> count{1, 1, 1};
  for (int k = 0; k < D; ++k) count[k] = static_cast<int>(std::floor((hi[k] - lo[k]) / spacing));
  // Vertical axis outermost so that a partial fill is a flat-topped column.
  std::size_t added = 0;
  const int nz = D == 3 ? count[2] : 1;
  for (int iy = 0; iy < count[1]; ++iy)
    for (int iz = 0; iz < nz; ++iz)
      for (int ix = 0; ix < count[0]; ++ix) {
        if (added == max_n) return added;
        Vec<D> x = vec<D>(ix + 0.5, iy + 0.5, iz + 0.5) * spacing + lo;
        Vec<D> v;
        for (int k = 0; k < D; ++k) {
          x[k] += jitter * (2.0 * u01(rng) - 1.0);
          v[k] = vmax * (2.0 * u01(rng) - 1.0);
        }
        const double r = rmin + (rmax - rmin) * u01(rng);
        w.particles.add(x, r, density, mat, v);
        ++added;
      }
  return added;
}

// ---------------------------------------------------------------------------------------
// One collision, between grains 0 and 1 (a world without walls) or between grain 0 and
// wall 0. Body 1 is grain 0, body 2 is grain 1 or the wall, as in the contact laws.

template <int D>
double overlap(const World<D>& w) {
  const auto& P = w.particles;
  if (!w.walls.empty()) return P.radius[0] - (P.pos[0] - w.walls[0].point).dot(w.walls[0].normal);
  return P.radius[0] + P.radius[1] - (P.pos[1] - P.pos[0]).norm();
}

// Unit normal from body 1 to body 2.
template <int D>
Vec<D> contact_normal(const World<D>& w) {
  if (!w.walls.empty()) return -w.walls[0].normal;
  return (w.particles.pos[1] - w.particles.pos[0]).normalized();
}

// Normal velocity of body 2's centre relative to body 1's: negative while approaching.
template <int D>
double relative_normal_velocity(const World<D>& w) {
  const auto& P = w.particles;
  const Vec<D> v2 = w.walls.empty() ? P.vel[1] : w.walls[0].velocity;
  return (v2 - P.vel[0]).dot(contact_normal(w));
}

// Normal component of the contact force of the last step (on body 2).
template <int D>
double last_normal_force(const World<D>& w) {
  const Vec<D> f = w.walls.empty() ? w.particles.force[1] : w.walls[0].force;
  return f.dot(contact_normal(w));
}

struct ImpactResult {
  double duration = 0.0;     // contact duration (s)
  double max_overlap = 0.0;  // largest overlap at the steps (m)
  double max_force = 0.0;    // largest normal force (N, N/m in 2D)
  double approach = 0.0;     // normal approach speed before (m/s)
  double separation = 0.0;   // normal separation speed after (m/s)
};

// Runs one collision to its end. The world must start with the bodies overlapping by
// v dt / 2 (v the approach speed) and free of forces before: with positions moving
// linearly between steps, the overlap then starts exactly half a step before t = 0. The
// end is interpolated linearly between the last two steps, so the duration carries no
// error of order dt from where the contact starts or ends within a step.
template <int D>
ImpactResult run_impact(World<D>& w, std::size_t max_steps) {
  ImpactResult r;
  r.approach = -relative_normal_velocity(w);
  double d_prev = overlap(w);
  EXPECT_GT(d_prev, 0.0);
  r.max_overlap = d_prev;
  const double t0 = w.time - 0.5 * w.dt;
  for (std::size_t k = 0; k < max_steps; ++k) {
    const double t_prev = w.time;
    step(w);
    r.max_force = std::max(r.max_force, last_normal_force(w));
    const double d = overlap(w);
    if (d <= 0.0) {
      r.duration = t_prev + w.dt * d_prev / (d_prev - d) - t0;
      r.separation = relative_normal_velocity(w);
      return r;
    }
    r.max_overlap = std::max(r.max_overlap, d);
    d_prev = d;
  }
  ADD_FAILURE() << "collision did not end within " << max_steps << " steps";
  return r;
}

// Two grains of radii r1, r2 approaching along x at relative speed v with zero total
// momentum, overlapping by v dt / 2.
template <int D>
void place_pair(World<D>& w, double r1, double r2, double density, std::uint16_t mat, double v) {
  auto& P = w.particles;
  const double x1 = r1 + r2 - 0.5 * v * w.dt;
  const double m1 = density * Dim<D>::volume(r1), m2 = density * Dim<D>::volume(r2);
  P.add(vec<D>(0.0, 0.0), r1, density, mat, vec<D>(v * m2 / (m1 + m2), 0.0));
  P.add(vec<D>(x1, 0.0), r2, density, mat, vec<D>(-v * m1 / (m1 + m2), 0.0));
}

// A grain above the floor plane y = 0 moving at (vt, -vn), overlapping it by vn dt / 2.
template <int D>
void place_on_floor(World<D>& w, double r, double density, std::uint16_t mat, double vn,
                    double vt = 0.0) {
  w.particles.add(vec<D>(0.0, r - 0.5 * vn * w.dt), r, density, mat, vec<D>(vt, -vn));
}

// ---------------------------------------------------------------------------------------
// Closed forms of the linear spring-dashpot (mass m*, stiffness kn, damping ratio beta,
// approach speed v): the overlap is v/wd exp(-beta w t) sin(wd t) during the contact.
struct LinearImpactTheory {
  double w, wd, zeta, duration, max_overlap;
  // The force turns attractive at t = attractive_from (= duration when undamped), where
  // the separating speed is largest.
  double attractive_from, max_separation_speed;
  LinearImpactTheory(double mstar, double kn, double beta, double v) {
    w = std::sqrt(kn / mstar);
    zeta = beta * w;
    wd = w * std::sqrt(1.0 - beta * beta);
    duration = std::numbers::pi / wd;
    const double tm = std::atan2(wd, zeta) / wd;  // zero velocity
    max_overlap = v / wd * std::exp(-zeta * tm) * std::sin(wd * tm);
    // Zero acceleration: tan(wd t) = 2 zeta wd / (zeta^2 - wd^2), with wd t in (pi/2, pi].
    const double ts = (std::numbers::pi - std::atan2(2.0 * zeta * wd, wd * wd - zeta * zeta)) / wd;
    attractive_from = ts;
    max_separation_speed =
        -v * std::exp(-zeta * ts) * (std::cos(wd * ts) - zeta / wd * std::sin(wd * ts));
  }
};

// Clumps of template `t` (scale 0.01, density 2600) on a jittered lattice of counts[0] x
// counts[1] (x counts[2]) sites `spacing` apart, created in shuffled order (unrelated to the
// cells) with random orientations, and thrown towards the lattice's centre at `speed` times
// their distance from it, so that they collide.
template <int D>
void throw_clumps_together(World<D>& w, const ResolvedClump<D>& t, std::array<int, 3> counts,
                           double spacing, double jitter, double speed, std::uint16_t mat,
                           std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec<D>> sites;
  for (int i = 0; i < counts[0]; ++i)
    for (int j = 0; j < counts[1]; ++j)
      for (int l = 0; l < (D == 3 ? counts[2] : 1); ++l) sites.push_back(vec<D>(i, j, l) * spacing);
  std::shuffle(sites.begin(), sites.end(), rng);
  const Vec<D> centre = vec<D>(0.5 * spacing * (counts[0] - 1), 0.5 * spacing * (counts[1] - 1),
                               0.5 * spacing * (counts[2] - 1));
  for (const Vec<D>& site : sites) {
    Vec<D> x = site;
    for (int k = 0; k < D; ++k) x[k] += jitter * (2.0 * u(rng) - 1.0);
    typename Dim<D>::Orient q;
    if constexpr (D == 2)
      q = 6.0 * u(rng);
    else
      q = random_orientation<3>(u(rng), u(rng), u(rng));
    add_clump(w, t, x, q, 0.01, 2600.0, mat, Vec<D>(-speed * (x - centre)));
  }
}

}  // namespace geodem::test
