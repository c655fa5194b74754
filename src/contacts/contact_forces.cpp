#include "contacts/contact_forces.hpp"

#include <algorithm>

#include "contacts/contact_law.hpp"

namespace geodem {

namespace {

template <int D>
void note_overlap(World<D>& world, std::size_t i, std::int64_t partner, double ratio) {
  if (world.overlap_offender >= 0) return;
  world.overlap_offender = static_cast<std::int64_t>(i);
  world.overlap_partner = partner;
  world.overlap_ratio = ratio;
}

// Grain-grain contacts. `Extras`: the contacts carry rolling springs and bond states
// (a separate instantiation, so that plain frictional packings pay nothing for them).
template <int D, bool Measure, bool Extras>
void grain_pairs(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  auto& P = world.particles;
  auto& L = world.nlist;
  const std::size_t n = P.size();
  const double dt = world.dt;
  const std::size_t nmat = world.materials.size();
  auto& st = world.stats;
  // Raw pointers: the compiler then knows the arrays do not move inside the loops.
  const Vec* __restrict pos = P.pos.data();
  const Vec* __restrict vel = P.vel.data();
  const Rot* __restrict angvel = P.angvel.data();
  const double* __restrict radius = P.radius.data();
  const double* __restrict inv_mass = P.inv_mass.data();
  const std::uint16_t* __restrict material = P.material.data();
  Vec* __restrict force = P.force.data();
  Rot* __restrict torque = P.torque.data();
  const std::uint32_t* __restrict start = L.start.data();
  const std::uint32_t* __restrict other = L.other.data();
  Vec* __restrict spring = L.spring.data();
  ContactExtra<D>* __restrict extra = L.extra.data();
  const PairLaw* pair_laws = world.pair_laws.data();
  const double overlap_limit = world.overlap_limit;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = start[i], e = start[i + 1];
    if (b == e) continue;
    const Vec xi = pos[i];
    const Vec vi = vel[i];
    const Rot wi = angvel[i];
    const double ri = radius[i], imi = inv_mass[i];
    const PairLaw* laws = pair_laws + material[i] * nmat;
    Vec fi = Vec::Zero();
    Rot ti = Dim<D>::zero_rot();
    for (std::uint32_t k = b; k < e; ++k) {
      const std::uint32_t j = other[k];
      const Vec d = pos[j] - xi;
      const double rj = radius[j];
      const double rs = ri + rj;
      const double dist2 = d.squaredNorm();
      bool bonded = false;
      if constexpr (Extras) bonded = extra[k].bonded;
      if (dist2 >= rs * rs && !bonded) {
        // Apart: the history ends (written only when there is one, to spare stores).
        if (spring[k].squaredNorm() != 0.0) spring[k] = Vec::Zero();
        if constexpr (Extras) {
          if (Dim<D>::rot_norm2(extra[k].roll) != 0.0 || extra[k].twist != 0.0)
            extra[k] = ContactExtra<D>{};
        }
        continue;
      }
      const double dist = std::sqrt(dist2);
      const Vec nrm = d * (1.0 / dist);
      const double delta = rs - dist;
      if (delta > overlap_limit * std::min(ri, rj)) [[unlikely]]
        note_overlap(world, i, static_cast<std::int64_t>(j), delta / std::min(ri, rj));
      const double ai = ri - 0.5 * delta, aj = rj - 0.5 * delta;  // centre-to-contact lengths
      // Surface velocities at the contact point.
      const Vec vrel =
          (vel[j] - Dim<D>::cross(angvel[j], aj * nrm)) - (vi + Dim<D>::cross(wi, ai * nrm));
      const PairLaw& law = laws[material[j]];
      double fn;
      Vec f;
      if (!bonded) {
        f = contact_force<D>(law, ri, rj, imi + inv_mass[j], nrm, delta, vrel, dt, spring[k], fn);
      } else {
        bool broken;
        f = bonded_contact_force<D>(law, ri, rj, imi + inv_mass[j], nrm, delta, vrel, dt, spring[k],
                                    fn, broken);
        if (broken) {
          extra[k].bonded = 0;
          ++world.broken_bonds;
          if (delta <= 0.0) {
            extra[k] = ContactExtra<D>{};
            continue;
          }
        }
      }
      force[j] += f;
      fi -= f;
      // Torques: lever arms +ai n (grain i) and -aj n (grain j); the normal part gives none.
      const Rot tq = Dim<D>::cross(nrm, f);
      ti -= ai * tq;
      torque[j] -= aj * tq;
      if constexpr (Extras) {
        if (law.rolling()) {
          const Rot m = rolling_moment<D>(law, tangential_stiffness(law, ri, rj, delta), ri, rj,
                                          nrm, Rot(angvel[j] - wi), dt, fn, extra[k]);
          torque[j] += m;
          ti -= m;
        }
      }
      if constexpr (Measure) {
        st.fabric_stress += d * f.transpose();
        st.sum_force += f.norm();
        ++st.contacts;
        if (fn > 0.0 && law.law == LawKind::kLinear)
          st.elastic_energy += 0.5 * fn * fn / law.linear_kn(ri, rj);
      }
    }
    force[i] += fi;
    torque[i] += ti;
  }
}

template <int D, bool Measure, bool Extras>
void grain_walls(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  auto& P = world.particles;
  auto& L = world.nlist;
  const std::size_t n = P.size();
  const double dt = world.dt;
  auto& st = world.stats;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = L.wall_start[i], e = L.wall_start[i + 1];
    for (std::uint32_t k = b; k < e; ++k) {
      auto& wall = world.walls[L.wall[k]];
      const Vec xi = P.pos[i];
      const double ri = P.radius[i];
      Vec q;
      double gap;
      Vec nrm;  // from the grain to the wall
      if (wall.kind == WallKind::kPlane) {
        gap = (xi - wall.point).dot(wall.normal);
        nrm = -wall.normal;
      } else {
        if (!wall_closest(wall, xi, q)) {
          L.wall_spring[k] = Vec::Zero();
          if constexpr (Extras) L.wall_extra[k] = ContactExtra<D>{};
          continue;
        }
        const Vec d = q - xi;
        gap = d.norm();
        if (gap <= 0.0) continue;  // centre exactly on the segment: no defined normal
        nrm = d / gap;
      }
      const double delta = ri - gap;
      if (delta <= 0.0) {
        L.wall_spring[k] = Vec::Zero();
        if constexpr (Extras) L.wall_extra[k] = ContactExtra<D>{};
        continue;
      }
      if (delta > world.overlap_limit * ri) [[unlikely]]
        note_overlap(world, i, -1 - static_cast<std::int64_t>(L.wall[k]), delta / ri);
      const double a = ri - 0.5 * delta;
      const Vec vrel = wall.velocity - (P.vel[i] + Dim<D>::cross(P.angvel[i], a * nrm));
      const PairLaw& law = world.wall_law(P.material[i], L.wall[k]);
      double fn;
      const Vec f = contact_force<D>(law, ri, wall_partner_radius(law, ri), P.inv_mass[i], nrm,
                                     delta, vrel, dt, L.wall_spring[k], fn);
      P.force[i] -= f;
      P.torque[i] -= a * Dim<D>::cross(nrm, f);
      if constexpr (Extras) {
        if (law.rolling()) {
          // The wall does not rotate: wrel = -w_grain; the grain is body 1.
          const auto m = rolling_moment<D>(
              law, tangential_stiffness(law, ri, wall_partner_radius(law, ri), delta), ri,
              kWallRadius, nrm, -P.angvel[i], dt, fn, L.wall_extra[k]);
          P.torque[i] -= m;
        }
      }
      wall.force += f;
      wall.stiffness += law.law == LawKind::kLinear ? law.linear_kn(ri, ri) : 1.5 * fn / delta;
      if constexpr (Measure) {
        st.fabric_stress += (a * nrm) * f.transpose();
        st.sum_force += f.norm();
        ++st.wall_contacts;
        if (fn > 0.0 && law.law == LawKind::kLinear)
          st.elastic_energy += 0.5 * fn * fn / law.linear_kn(ri, ri);
      }
    }
  }
}

}  // namespace

template <int D>
void compute_contact_forces(World<D>& world) {
  for (auto& w : world.walls) {
    w.force = Dim<D>::Vec::Zero();
    w.stiffness = 0.0;
  }
  const bool extras = world.contact_extras;
  if (world.measure_this_step) {
    world.stats = ContactStats<D>{};
    if (extras) {
      grain_pairs<D, true, true>(world);
      grain_walls<D, true, true>(world);
    } else {
      grain_pairs<D, true, false>(world);
      grain_walls<D, true, false>(world);
    }
  } else if (extras) {
    grain_pairs<D, false, true>(world);
    grain_walls<D, false, true>(world);
  } else {
    grain_pairs<D, false, false>(world);
    grain_walls<D, false, false>(world);
  }
}

template void compute_contact_forces<2>(World<2>&);
template void compute_contact_forces<3>(World<3>&);

}  // namespace geodem
