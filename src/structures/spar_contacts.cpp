#include "structures/spar_contacts.hpp"

#include <algorithm>
#include <cmath>

#include "contacts/contact_law.hpp"
#include "structures/spar_geometry.hpp"

namespace geodem {

namespace {

// Moves the tangential springs of contacts that left their element for a neighbour
// to the neighbour's entry of the same grain, before any force is computed, so that
// the spring is never lost for a step. A neighbour entry with a spring of its own is
// a distinct contact (concave bend) and keeps it.
template <int D>
void hand_over_springs(World<D>& world, std::size_t i, std::uint32_t b, std::uint32_t e) {
  const auto& S = world.spars;
  auto& L = world.nlist;
  for (std::uint32_t k = b; k < e; ++k) {
    if (spring_norm2<D>(L.spar_spring[k]) == 0.0) continue;
    const std::size_t el = L.spar[k];
    const SparPoint<D> p = spar_point(S, el, world.particles.pos[i]);
    if (p.region == SparRegion::kOwned) continue;
    const std::int32_t to = p.region == SparRegion::kToNext ? S.next[el] : S.prev[el];
    for (std::uint32_t m = b; m < e; ++m)
      if (static_cast<std::int32_t>(L.spar[m]) == to) {
        if (spring_norm2<D>(L.spar_spring[m]) == 0.0) L.spar_spring[m] = L.spar_spring[k];
        break;
      }
    L.spar_spring[k] = unloaded_spring<D>();
  }
}

}  // namespace

template <int D>
void compute_spar_contacts(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  auto& S = world.spars;
  for (auto& f : S.force) f.setZero();
  S.contact_normal.assign(S.elements(), 0.0);
  auto& P = world.particles;
  auto& L = world.nlist;
  if (S.empty() || L.spar_start.size() != P.size() + 1) return;
  const double dt = world.dt;
  auto& st = world.stats;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const std::uint32_t b = L.spar_start[i], e = L.spar_start[i + 1];
    if (b == e) continue;
    hand_over_springs(world, i, b, e);
    const Vec xi = P.pos[i];
    const double ri = P.radius[i];
    for (std::uint32_t k = b; k < e; ++k) {
      const std::size_t el = L.spar[k];
      const SparPoint<D> p = spar_point(S, el, xi);
      const Vec d = p.closest - xi;
      const double dist = d.norm();
      const double delta = ri + S.half_thickness[el] - dist;
      if (p.region != SparRegion::kOwned || delta <= 0.0 || dist <= 0.0) {
        L.spar_spring[k] = unloaded_spring<D>();
        continue;
      }
      const Vec nrm = d / dist;  // from the grain to the element
      if (delta > world.overlap_limit * ri) [[unlikely]] {
        if (world.overlap_offender < 0) {
          world.overlap_offender = static_cast<std::int64_t>(i);
          world.overlap_partner = -1 - static_cast<std::int64_t>(world.walls.size() + el);
          world.overlap_ratio = delta / ri;
        }
      }
      const std::uint32_t na = S.node_a[el], nb = S.node_b[el];
      const double wa = 1.0 - p.t, wb = p.t;
      const Vec v_el = wa * S.vel[na] + wb * S.vel[nb];
      const double a = ri - 0.5 * delta;
      const Vec vrel = v_el - (P.vel[i] + Dim<D>::cross(P.angvel[i], a * nrm));
      // Inverse mass of the element at the contact point: sum of w^2 / m over its nodes.
      const double inv_m_el = (S.driven(na) ? 0.0 : wa * wa / S.inertial_mass[na]) +
                              (S.driven(nb) ? 0.0 : wb * wb / S.inertial_mass[nb]);
      const PairLaw& law = world.pair_law(P.material[i], S.material[el]);
      double fn;
      const Vec f =
          contact_force<D>(law, ri, wall_partner_radius(law, ri), P.inv_mass[i] + inv_m_el, nrm,
                           delta, vrel, dt, L.spar_spring[k], fn);
      S.contact_normal[el] += std::max(fn, 0.0);
      S.force[na] += wa * f;
      S.force[nb] += wb * f;
      P.force[i] -= f;
      P.torque[i] -= a * Dim<D>::cross(nrm, f);
      if (world.measure_this_step) {
        st.fabric_stress += (a * nrm) * f.transpose();
        st.sum_force += f.norm();
        ++st.spar_contacts;
      }
    }
  }
}

template void compute_spar_contacts<2>(World<2>&);
template void compute_spar_contacts<3>(World<3>&);

}  // namespace geodem
