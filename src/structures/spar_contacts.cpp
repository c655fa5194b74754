#include "structures/spar_contacts.hpp"

#include <algorithm>
#include <cmath>

#include "base/exact_sum.hpp"
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

// Slots of the exact sums: the elements' normal loads, then the nodes' force components.
template <int D>
std::size_t force_slot(const SparChains<D>& S, std::size_t node, int c) {
  return S.elements() + node * D + static_cast<std::size_t>(c);
}

// The chains' loads and the contact statistics summed over ranks; one more slot, last, for an
// overlap beyond the limit met on any rank (so that every rank stops).
template <int D>
void reduce_spar_loads(World<D>& world, std::vector<ExactSum>& sums, std::vector<ExactSum>& stats) {
  auto& S = world.spars;
  const std::size_t ns = sums.size(), nst = stats.size();
  sums.resize(ns + nst + 1);
  for (std::size_t k = 0; k < nst; ++k) sums[ns + k] = stats[k];
  if (world.overlap_offender >= 0) sums.back().add(1.0);
  world.domain->sum(sums);
  world.overlap_elsewhere = world.overlap_elsewhere || sums.back().value() > 0.0;
  for (std::size_t e = 0; e < S.elements(); ++e) S.contact_normal[e] = sums[e].value();
  for (std::size_t i = 0; i < S.nodes(); ++i)
    for (int c = 0; c < D; ++c) S.force[i][c] = sums[force_slot(S, i, c)].value();
  if (nst == 0) return;
  auto& st = world.stats;
  const ExactSum* t = sums.data() + ns;
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < D; ++c) st.fabric_stress(r, c) += t[r * D + c].value();
  st.sum_force += t[D * D].value();
  st.spar_contacts += static_cast<std::size_t>(t[D * D + 1].value());
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
  if (S.empty()) return;
  const bool listed = L.spar_start.size() == P.size() + 1;
  if (!listed && !world.domain) return;
  const double dt = world.dt;
  auto& st = world.stats;
  // A decomposed world: every rank holds the whole chains and computes its own grains'
  // contacts with them; the loads on the nodes and elements are each rank's exact sums added
  // over ranks, so that every rank moves the chains alike (docs/parallel.md).
  const bool exact = world.domain != nullptr;
  static thread_local std::vector<ExactSum> sums, stats;  // kept: the step allocates nothing
  if (exact) {
    sums.assign(S.elements() + S.nodes() * D, ExactSum{});
    stats.assign(world.measure_this_step ? D * D + 2 : 0, ExactSum{});
  }
  for (std::size_t i = 0; listed && i < P.size(); ++i) {
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
      if (exact) {  // a decomposed world: summed exactly, then over ranks (below)
        sums[el].add(std::max(fn, 0.0));
        for (int c = 0; c < D; ++c) {
          sums[force_slot(S, na, c)].add(wa * f[c]);
          sums[force_slot(S, nb, c)].add(wb * f[c]);
        }
      } else {
        S.contact_normal[el] += std::max(fn, 0.0);
        S.force[na] += wa * f;
        S.force[nb] += wb * f;
      }
      P.force[i] -= f;
      P.torque[i] -= a * Dim<D>::cross(nrm, f);
      if (world.measure_this_step) {
        const Vec lever = a * nrm;
        if (exact) {
          for (int r = 0; r < D; ++r)
            for (int c = 0; c < D; ++c)
              stats[static_cast<std::size_t>(r * D + c)].add(lever[r] * f[c]);
          stats[D * D].add(f.norm());
          stats[D * D + 1].add(1.0);
          continue;
        }
        st.fabric_stress += lever * f.transpose();
        st.sum_force += f.norm();
        ++st.spar_contacts;
      }
    }
  }
  if (exact) reduce_spar_loads(world, sums, stats);
}

template void compute_spar_contacts<2>(World<2>&);
template void compute_spar_contacts<3>(World<3>&);

}  // namespace geodem
