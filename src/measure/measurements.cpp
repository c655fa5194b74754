#include "measure/measurements.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "base/parallel.hpp"

namespace geodem {

namespace {

// Sum of grain(i) over a decomposed world's own grains and clump(c) over its own clumps, exact
// and added over ranks: every rank has the domain's sum, the same for any number of ranks.
template <int D, typename GrainTerm, typename ClumpTerm>
double owned_body_sum(const World<D>& world, GrainTerm&& grain, ClumpTerm&& clump) {
  const auto& P = world.particles;
  std::vector<ExactSum> s(1);
  for (std::size_t i = 0; i < P.size(); ++i)
    if (!(P.flags[i] & kGhost)) s[0].add(grain(i));
  for (std::size_t c = 0; c < world.clumps.owned(); ++c) s[0].add(clump(c));
  world.domain->sum(s);
  return s[0].value();
}

// Sum of term(i) over the grains: in blocks (base/parallel.hpp), or, in a decomposed world
// (docs/parallel.md), over each rank's own grains exactly and added over ranks.
template <int D, typename Term>
double grain_sum(const World<D>& world, Term&& term) {
  if (!world.domain) return ordered_sum(world.particles.size(), world.threads, 0.0, term);
  return owned_body_sum(world, term, [](std::size_t) { return 0.0; });
}

}  // namespace

// Bodies are the grains that are not clump members, and the clumps.
template <int D>
double kinetic_energy(const World<D>& world) {
  const auto& P = world.particles;
  const auto& C = world.clumps;
  auto grain = [&](std::size_t i) {
    if (P.inv_mass[i] == 0.0 || P.member(i)) return 0.0;
    return 0.5 * P.vel[i].squaredNorm() / P.inv_mass[i] +
           0.5 * Dim<D>::rot_norm2(P.angvel[i]) / P.inv_inertia[i];
  };
  auto rotation = [&](std::size_t c) {
    if constexpr (D == 2)
      return 0.5 * C.inertia[c] * C.angvel[c] * C.angvel[c];
    else
      return 0.5 * C.angmom[c].dot(C.angvel[c]);
  };
  if (world.domain)
    return owned_body_sum(world, grain, [&](std::size_t c) {
      return 0.5 * C.vel[c].squaredNorm() / C.inv_mass[c] + rotation(c);
    });
  double e = grain_sum(world, grain);
  for (std::size_t c = 0; c < C.size(); ++c) {
    e += 0.5 * C.vel[c].squaredNorm() / C.inv_mass[c];
    if constexpr (D == 2)
      e += 0.5 * C.inertia[c] * C.angvel[c] * C.angvel[c];
    else
      e += 0.5 * C.angmom[c].dot(C.angvel[c]);
  }
  return e;
}

template <int D>
double gravity_energy(const World<D>& world) {
  const auto& P = world.particles;
  const auto& C = world.clumps;
  auto grain = [&](std::size_t i) {
    return P.inv_mass[i] > 0.0 && !P.member(i) ? P.pos[i].dot(world.gravity) / P.inv_mass[i] : 0.0;
  };
  if (world.domain)
    return -owned_body_sum(
        world, grain, [&](std::size_t c) { return C.pos[c].dot(world.gravity) / C.inv_mass[c]; });
  double e = -grain_sum(world, grain);
  for (std::size_t c = 0; c < C.size(); ++c) e -= C.pos[c].dot(world.gravity) / C.inv_mass[c];
  return e;
}

template <int D>
double body_weight(const World<D>& world) {
  const auto& P = world.particles;
  double m = 0.0;
  if (world.domain) {
    const auto& C = world.clumps;
    m = owned_body_sum(
        world,
        [&](std::size_t i) {
          return P.inv_mass[i] > 0.0 && !P.member(i) ? 1.0 / P.inv_mass[i] : 0.0;
        },
        [&](std::size_t c) { return 1.0 / C.inv_mass[c]; });
    return m * world.gravity.norm();
  } else {
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.inv_mass[i] > 0.0 && !P.member(i)) m += 1.0 / P.inv_mass[i];
  }
  for (double im : world.clumps.inv_mass) m += 1.0 / im;
  return m * world.gravity.norm();
}

template <int D>
double solid_volume(const World<D>& world) {
  const auto& P = world.particles;
  auto grain = [&](std::size_t i) { return P.member(i) ? 0.0 : Dim<D>::volume(P.radius[i]); };
  if (world.domain)
    return owned_body_sum(world, grain, [&](std::size_t c) { return world.clumps.volume[c]; });
  double v = grain_sum(world, grain);
  for (double cv : world.clumps.volume) v += cv;
  return v;
}

template <int D>
std::size_t intact_bonds(const World<D>& world) {
  if (world.domain) {  // each bond counted on the rank that owns its row's grain
    const auto& L = world.nlist;
    const auto& P = world.particles;
    std::vector<ExactSum> n(1);
    for (std::size_t i = 0; i + 1 < L.start.size() && !L.extra.empty(); ++i)
      if (!(P.flags[i] & kGhost))
        for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) n[0].add(L.extra[k].bonded);
    world.domain->sum(n);
    return static_cast<std::size_t>(n[0].value());
  }
  std::size_t n = 0;
  for (const auto& e : world.nlist.extra) n += e.bonded;
  return n;
}

template <int D>
double unbalanced_force_ratio(const World<D>& world) {
  const auto& P = world.particles;
  const std::size_t nc =
      world.stats.contacts + world.stats.wall_contacts + world.stats.spar_contacts;
  if (nc == 0 || world.stats.sum_force <= 0.0) return std::numeric_limits<double>::quiet_NaN();
  // Fixed and held grains and clump members do not count.
  auto counts = [&](std::size_t i) { return P.inv_mass[i] != 0.0 && P.free_body(i); };
  auto resultant = [&](std::size_t i) {
    return counts(i) ? (P.force[i] + world.gravity / P.inv_mass[i]).norm() : 0.0;
  };
  const auto& C = world.clumps;  // resultants summed at the last integration
  auto free_clump = [&](std::size_t c) { return C.held.empty() || !C.held[c]; };
  if (world.domain) {
    const double sum = owned_body_sum(world, resultant, [&](std::size_t c) {
      return free_clump(c) ? (C.force[c] + world.gravity / C.inv_mass[c]).norm() : 0.0;
    });
    const double nfree = owned_body_sum(
        world, [&](std::size_t i) { return counts(i) ? 1.0 : 0.0; },
        [&](std::size_t c) { return free_clump(c) ? 1.0 : 0.0; });
    if (nfree == 0.0) return 0.0;
    return (sum / nfree) / (world.stats.sum_force / static_cast<double>(nc));
  }
  double sum = grain_sum(world, resultant);
  std::size_t nfree = ordered_sum(P.size(), world.threads, std::size_t{0},
                                  [&](std::size_t i) -> std::size_t { return counts(i) ? 1 : 0; });
  for (std::size_t c = 0; c < C.size(); ++c) {
    if (!free_clump(c)) continue;
    sum += (C.force[c] + world.gravity / C.inv_mass[c]).norm();
    ++nfree;
  }
  if (nfree == 0) return 0.0;
  return (sum / static_cast<double>(nfree)) / (world.stats.sum_force / static_cast<double>(nc));
}

template <int D>
typename Dim<D>::Tensor average_stress(const World<D>& world, double volume) {
  const auto& s = world.stats.fabric_stress;
  return 0.5 * (s + s.transpose()) / volume;
}

template <int D>
typename Dim<D>::Tensor cell_stress(const World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  typename Dim<D>::Tensor s = world.cell_fabric;
  const auto& P = world.particles;
  // (a decomposed cell's sum took its members at their clumps' centres: ExactTally)
  if (world.clumps.size() > 0 && !world.domain)
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.clump[i] == kNoClump) continue;
      const Vec arm = P.pos[i] - world.clumps.pos[P.clump[i]];
      s -= arm * P.force[i].transpose();
    }
  return 0.5 * (s + s.transpose()) / world.cell.volume();
}

template <int D>
double coordination_number(const World<D>& world) {
  const std::size_t n = body_count(world);
  return n ? 2.0 * static_cast<double>(world.stats.contacts) / static_cast<double>(n) : 0.0;
}

namespace {

// Integral of sqrt(r^2 - t^2) dt from 0 to t (|t| <= r).
double half_chord_integral(double t, double r) {
  t = std::clamp(t, -r, r);
  return 0.5 * (t * std::sqrt(std::max(r * r - t * t, 0.0)) + r * r * std::asin(t / r));
}

// Area of the disc of radius r at the origin inside {X < x, Y < y}.
double quadrant_area(double x, double y, double r) {
  if (y <= -r || x <= -r) return 0.0;
  const double xc = std::min(x, r);
  auto H = [r](double t) { return half_chord_integral(t, r); };
  if (y >= r) return 2.0 * (H(xc) - H(-r));
  const double s = std::sqrt(r * r - y * y);  // |t| <= s: the chord crosses Y = y
  double area = 0.0;
  // t in [-r, -s] and [s, r]: chord entirely below y (y > 0) or above it (y < 0).
  if (y > 0.0) {
    area += 2.0 * (H(std::min(xc, -s)) - H(-r));
    if (xc > s) area += 2.0 * (H(xc) - H(s));
  }
  // t in [-s, s]: length y + h(t).
  if (xc > -s) {
    const double hi = std::min(xc, s);
    area += y * (hi + s) + (H(hi) - H(-s));
  }
  return area;
}

// 16-point Gauss-Legendre nodes and weights on [-1, 1].
constexpr std::array<double, 8> kGaussX = {
    0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
    0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
constexpr std::array<double, 8> kGaussW = {
    0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
    0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};

}  // namespace

double disc_rectangle_area(double cx, double cy, double r, double x0, double y0, double x1,
                           double y1) {
  if (x1 <= x0 || y1 <= y0) return 0.0;
  x0 -= cx, x1 -= cx, y0 -= cy, y1 -= cy;
  return quadrant_area(x1, y1, r) - quadrant_area(x0, y1, r) - quadrant_area(x1, y0, r) +
         quadrant_area(x0, y0, r);
}

namespace {

// The volume of grain i inside the box.
template <int D>
double grain_volume_in_box(const World<D>& world, const Box<D>& box, std::size_t i) {
  const auto& P = world.particles;
  double v = 0.0;
  const auto& x = P.pos[i];
  const double r = P.radius[i];
  bool inside = true, outside = false;
  for (int k = 0; k < D; ++k) {
    if (x[k] - r < box.lo[k] || x[k] + r > box.hi[k]) inside = false;
    if (x[k] + r <= box.lo[k] || x[k] - r >= box.hi[k]) outside = true;
  }
  if (outside) return 0.0;
  if (inside) return Dim<D>::volume(r);
  if constexpr (D == 2) {
    v += disc_rectangle_area(x[0], x[1], r, box.lo[0], box.lo[1], box.hi[0], box.hi[1]);
  } else {
    // Slices along z: substitution z = cz + r sin(theta) removes the end singularity;
    // the slice areas have kinks where a slice starts touching a face, so the range is
    // split at those heights and each piece integrated with 16 Gauss points.
    const double za = std::max(box.lo[2], x[2] - r), zb = std::min(box.hi[2], x[2] + r);
    const double ta = std::asin(std::clamp((za - x[2]) / r, -1.0, 1.0));
    const double tb = std::asin(std::clamp((zb - x[2]) / r, -1.0, 1.0));
    std::array<double, 12> cuts{ta, tb};  // ends + at most 8 kinks
    int nc = 2;
    for (int k = 0; k < 2; ++k)
      for (double face : {box.lo[k], box.hi[k]}) {
        const double dist = std::abs(face - x[k]);
        if (dist >= r) continue;
        const double rho_t = std::acos(dist / r);  // |theta| where the slice radius = dist
        for (double t : {-rho_t, rho_t})
          if (t > ta && t < tb) cuts[nc++] = t;
      }
    for (int a = 1; a < nc; ++a)  // insertion sort of at most 10 values
      for (int b = a; b > 0 && cuts[b - 1] > cuts[b]; --b) std::swap(cuts[b - 1], cuts[b]);
    for (int c = 0; c + 1 < nc; ++c) {
      const double a = cuts[c], b = cuts[c + 1], half = 0.5 * (b - a), mid = 0.5 * (a + b);
      // At a kink the slice area behaves as |theta - kink|^(3/2); the cubic map
      // s = u (3 - u^2) / 2 (zero slope at both ends) turns that into a smooth integrand.
      for (int g = 0; g < 8; ++g)
        for (double sgn : {-1.0, 1.0}) {
          const double u = sgn * kGaussX[g];
          const double t = mid + half * 0.5 * u * (3.0 - u * u);
          const double jac = half * 1.5 * (1.0 - u * u);
          const double rho = r * std::cos(t);
          v += kGaussW[g] * jac * r * std::cos(t) *
               disc_rectangle_area(x[0], x[1], rho, box.lo[0], box.lo[1], box.hi[0], box.hi[1]);
        }
    }
  }
  return v;
}

}  // namespace

template <int D>
double solid_volume_in_box(const World<D>& world, const Box<D>& box) {
  auto term = [&](std::size_t i) { return grain_volume_in_box(world, box, i); };
  if (world.domain) return grain_sum(world, term);
  double v = 0.0;  // in grain order
  for (std::size_t i = 0; i < world.particles.size(); ++i) v += term(i);
  return v;
}

template <int D>
std::uint64_t broken_bond_count(const World<D>& world) {
  // (each rank counted the bonds of its rows)
  return world.domain ? world.domain->count_over_ranks(world.broken_bonds) : world.broken_bonds;
}

template <int D>
double radius_of_grain(const World<D>& world, std::uint32_t id) {
  const auto& P = world.particles;
  double r = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.id[i] == id && !(P.flags[i] & kGhost)) r = P.radius[i];
  if (world.domain) r = world.domain->min_over_ranks(r);
  return std::isfinite(r) ? r : 0.0;
}

template double radius_of_grain<2>(const World<2>&, std::uint32_t);
template double radius_of_grain<3>(const World<3>&, std::uint32_t);
template double kinetic_energy<2>(const World<2>&);
template double kinetic_energy<3>(const World<3>&);
template double gravity_energy<2>(const World<2>&);
template double gravity_energy<3>(const World<3>&);
template double body_weight<2>(const World<2>&);
template double body_weight<3>(const World<3>&);
template Dim<2>::Tensor cell_stress<2>(const World<2>&);
template Dim<3>::Tensor cell_stress<3>(const World<3>&);
template double solid_volume<2>(const World<2>&);
template double solid_volume<3>(const World<3>&);
template std::size_t intact_bonds<2>(const World<2>&);
template std::uint64_t broken_bond_count<2>(const World<2>&);
template std::uint64_t broken_bond_count<3>(const World<3>&);
template std::size_t intact_bonds<3>(const World<3>&);
template double unbalanced_force_ratio<2>(const World<2>&);
template double unbalanced_force_ratio<3>(const World<3>&);
template Dim<2>::Tensor average_stress<2>(const World<2>&, double);
template Dim<3>::Tensor average_stress<3>(const World<3>&, double);
template double coordination_number<2>(const World<2>&);
template double coordination_number<3>(const World<3>&);
template double solid_volume_in_box<2>(const World<2>&, const Box<2>&);
template double solid_volume_in_box<3>(const World<3>&, const Box<3>&);

}  // namespace geodem
