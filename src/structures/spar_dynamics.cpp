#include "structures/spar_dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "base/exact_sum.hpp"
#include "contacts/contact_law.hpp"
#include "structures/spar_geometry.hpp"

namespace geodem {

double axial_force(double J, double length, double rest_length, double thickness) {
  // Tension only: a slack element carries nothing (a sheet buckles freely) ...
  if (length >= rest_length) return J * (length / rest_length - 1.0);
  // ... until its nodes come closer than the sheet's thickness: the material folded up
  // between them cannot pass through itself. Without this an element pressed end to end
  // (a free end dragged by the soil, a trench fill settling along the sheet) could shrink to
  // nothing and turn inside out, its bending moment flipping sign at a length where the
  // bending springs' stiffness (k_b / l^2) far exceeds the time step's estimate.
  if (length < thickness) return -J * (thickness - length) / rest_length;
  return 0.0;
}

template <int D>
void spar_element_forces(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  auto& S = world.spars;
  for (std::size_t e = 0; e < S.elements(); ++e) {
    const std::uint32_t a = S.node_a[e], b = S.node_b[e];
    const Vec d = S.pos[b] - S.pos[a];
    const double len = d.norm();
    const double T = axial_force(S.stiffness[e], len, S.rest_length[e], 2.0 * S.half_thickness[e]);
    S.tension[e] = T;
    if (T != 0.0 && len > 0.0) {
      const Vec f = (T / len) * d;
      S.force[a] += f;
      S.force[b] -= f;
    }
  }
  if constexpr (D == 2) {
    // Bending: a moment M = k (phi - phi0) at the node between elements e and f, phi the
    // turn from e's direction to f's. With the potential k (phi - phi0)^2 / 2 and
    // d(theta)/dx = perp(u)/L at an element's end (-perp(u)/L at its start), the nodes
    // get F_a = -M perp(u1)/L1, F_c = -M perp(u2)/L2, F_n = -(F_a + F_c): no net force.
    for (const auto& c : S.chains) {
      if (c.bending == 0.0) continue;
      for (std::uint32_t k = 0; k + 2 < c.node_count; ++k) {
        const std::size_t e = c.first_element + k;
        const auto f = static_cast<std::size_t>(S.next[e]);
        const double M = c.bending * S.turn_from_rest(e);  // (the chain's k at hand)
        const Vec u1 = S.pos[S.node_b[e]] - S.pos[S.node_a[e]];
        const Vec u2 = S.pos[S.node_b[f]] - S.pos[S.node_a[f]];
        const Vec p1(-u1.y(), u1.x()), p2(-u2.y(), u2.x());  // perp(u) |u|
        const Vec fa = (-M / u1.squaredNorm()) * p1;
        const Vec fc = (-M / u2.squaredNorm()) * p2;
        S.force[S.node_a[e]] += fa;
        S.force[S.node_b[f]] += fc;
        S.force[S.node_b[e]] -= fa + fc;
      }
    }
  }
}

template <int D>
double integrate_spar_nodes(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  auto& S = world.spars;
  const double dt = world.dt, alpha = world.local_damping;
  double vmax2 = 0.0;
  for (std::size_t i = 0; i < S.nodes(); ++i) {
    if (!S.driven(i)) {
      Vec a = (S.force[i] + S.mass[i] * world.gravity) / S.inertial_mass[i];
      if (alpha > 0.0) {
        // Cundall's local damping on each component, as for the grains.
        for (int k = 0; k < D; ++k)
          a[k] -= std::copysign(alpha * std::abs(a[k]), S.vel[i][k] + 0.5 * dt * a[k]);
      }
      S.vel[i] += a * dt;
    }
    S.pos[i] += S.vel[i] * dt;
    vmax2 = std::max(vmax2, S.vel[i].squaredNorm());
  }
  return vmax2;
}

template <int D>
double spar_min_mass_over_stiffness(const World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  const auto& S = world.spars;
  double best = std::numeric_limits<double>::infinity();
  if (S.empty()) return best;
  static thread_local std::vector<Vec> k;
  k.assign(S.nodes(), Vec::Zero());
  for (std::size_t e = 0; e < S.elements(); ++e) {
    const Vec u = (S.pos[S.node_b[e]] - S.pos[S.node_a[e]]).normalized();
    // Axial spring J/L0 along u: k_aa += (J/L0) u_a^2 on both nodes.
    const Vec ke = (S.stiffness[e] / S.rest_length[e]) * u.cwiseProduct(u);
    k[S.node_a[e]] += ke;
    k[S.node_b[e]] += ke;
  }
  if constexpr (D == 2) {
    // A bending spring's stiffness is k_b g g^T with g = (1/l1, -(1/l1 + 1/l2), 1/l2) on
    // its three nodes (transverse). Its diagonal alone underestimates the largest
    // eigenvalue of a chain of springs (16 k_b/l^2 for equal elements against a diagonal of
    // 6 k_b/l^2); each node takes its Gershgorin row sum k_b |g_i| sum_j |g_j| instead.
    for (const auto& c : S.chains) {
      if (c.bending == 0.0) continue;
      for (std::uint32_t j = 0; j + 2 < c.node_count; ++j) {
        const std::size_t e = c.first_element + j;
        const double g1 = 1.0 / S.rest_length[e], g2 = 1.0 / S.rest_length[e + 1];
        const double sum = 2.0 * (g1 + g2);
        k[S.node_a[e]] += Vec::Constant(c.bending * g1 * sum);
        k[S.node_b[e]] += Vec::Constant(c.bending * (g1 + g2) * sum);
        k[S.node_b[e + 1]] += Vec::Constant(c.bending * g2 * sum);
      }
    }
  }
  // Grain contacts: the whole normal and tangential stiffness on both nodes (the
  // weights are at most 1), a slight overestimate that keeps the step safe.
  // A decomposed world: each rank has its own grains' contacts; their stiffness on each node
  // is summed exactly, then over ranks, so that every rank finds the same step.
  const auto& P = world.particles;
  const auto& L = world.nlist;
  static thread_local std::vector<ExactSum> contact_k;
  if (world.domain) contact_k.assign(S.nodes(), ExactSum{});
  if (L.spar_start.size() == P.size() + 1) {
    for (std::size_t i = 0; i < P.size(); ++i)
      for (std::uint32_t s = L.spar_start[i]; s < L.spar_start[i + 1]; ++s) {
        const std::size_t e = L.spar[s];
        const SparPoint<D> p = spar_point(S, e, P.pos[i]);
        const double gap = (p.closest - P.pos[i]).norm() - P.radius[i] - S.half_thickness[e];
        if (gap >= 0.0 || p.region != SparRegion::kOwned) continue;
        const PairLaw& law = world.pair_law(P.material[i], S.material[e]);
        const double r = P.radius[i], delta = -gap;
        const double r2 = wall_partner_radius(law, r);
        const NormalResult nr = normal_force(law, r, r2, 0.0, delta, 0.0);
        const double kn = normal_stiffness(law, r, r2, nr.fn, delta);
        if (world.domain) {
          contact_k[S.node_a[e]].add(std::max(kn, nr.kt));
          contact_k[S.node_b[e]].add(std::max(kn, nr.kt));
          continue;
        }
        const Vec ks = Vec::Constant(std::max(kn, nr.kt));
        k[S.node_a[e]] += ks;
        k[S.node_b[e]] += ks;
      }
  }
  if (world.domain) {
    world.domain->sum(contact_k);
    for (std::size_t i = 0; i < S.nodes(); ++i) k[i] += Vec::Constant(contact_k[i].value());
  }
  for (std::size_t i = 0; i < S.nodes(); ++i) {
    if (S.driven(i)) continue;
    const double kmax = k[i].maxCoeff();
    if (kmax > 0.0) best = std::min(best, S.inertial_mass[i] / kmax);
  }
  return best;
}

template <int D>
double spar_max_displacement(const World<D>& world) {
  const auto& S = world.spars;
  double d2 = 0.0;
  for (std::size_t i = 0; i < S.nodes(); ++i)
    d2 = std::max(d2, (S.pos[i] - S.pos_at_build[i]).squaredNorm());
  return std::sqrt(d2);
}

template void spar_element_forces<2>(World<2>&);
template void spar_element_forces<3>(World<3>&);
template double integrate_spar_nodes<2>(World<2>&);
template double integrate_spar_nodes<3>(World<3>&);
template double spar_min_mass_over_stiffness<2>(const World<2>&);
template double spar_min_mass_over_stiffness<3>(const World<3>&);
template double spar_max_displacement<2>(const World<2>&);
template double spar_max_displacement<3>(const World<3>&);

}  // namespace geodem
