#include "contacts/wall_rows.hpp"

#include "contacts/contact_batch.hpp"
#include "contacts/contact_law.hpp"
#include "contacts/plane_walls.hpp"

namespace geodem {

template <int D>
bool walls_by_plane_passes(const World<D>& world, bool measure, bool extras) {
  return !measure && !extras && contact_path() != ContactPath::kScalar && plane_walls_only(world);
}

template <int D, bool Measure, bool Extras>
void wall_rows(World<D>& world, std::size_t first, std::size_t last, SlabTally<D>& tally,
               bool planes) {
  using Vec = typename Dim<D>::Vec;
  auto& P = world.particles;
  auto& L = world.nlist;
  const double dt = world.dt;
  auto row = [&](std::size_t i, SlabTally<D>& t) {
    const std::uint32_t b = L.wall_start[i], e = L.wall_start[i + 1];
    for (std::uint32_t k = b; k < e; ++k) {
      const auto& wall = world.walls[L.wall[k]];
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
          L.wall_spring[k] = unloaded_spring<D>();
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
        L.wall_spring[k] = unloaded_spring<D>();
        if constexpr (Extras) L.wall_extra[k] = ContactExtra<D>{};
        continue;
      }
      if (delta > world.overlap_limit * ri) [[unlikely]]
        t.note_overlap(i, -1 - static_cast<std::int64_t>(L.wall[k]), delta / ri);
      // The contact point lies on the wall's surface: a rigid wall does not indent, so the
      // lever arm is R - delta (two grains share their overlap: R - delta / 2 each).
      const double a = ri - delta;
      const Vec vrel = wall.velocity - (P.vel[i] + Dim<D>::cross(P.angvel[i], a * nrm));
      const PairLaw& law = world.wall_law(P.material[i], L.wall[k]);
      const auto& shares = world.collision_shares.wall;
      const double inv_m = shares.empty() ? P.inv_mass[i] : P.inv_mass[i] * shares[k];
      double fn;
      const Vec f = contact_force<D>(law, ri, wall_partner_radius(law, ri), inv_m, nrm, delta, vrel,
                                     dt, L.wall_spring[k], fn);
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
      t.wall_force[L.wall[k]] += f;
      const double k_wall = normal_stiffness(law, ri, wall_partner_radius(law, ri), fn, delta);
      t.wall_stiffness[L.wall[k]] += k_wall;
      const double c_wall =
          world.tally_wall_dashpots
              ? normal_dashpot(law, ri, wall_partner_radius(law, ri), inv_m, delta)
              : 0.0;
      t.wall_dashpot[L.wall[k]] += c_wall;
      if (t.exact.on) t.exact.add_wall(L.wall[k], f, k_wall, c_wall);
      if constexpr (Measure) {
        t.stats.fabric_stress += (a * nrm) * f.transpose();
        t.stats.sum_force += f.norm();
        ++t.stats.wall_contacts;
        const double energy =
            fn > 0.0 ? normal_energy(law, ri, wall_partner_radius(law, ri), fn, delta) : 0.0;
        if (fn > 0.0) t.stats.elastic_energy += energy;
        if (t.exact.on) t.exact.add_contact(Vec(a * nrm), f, energy, true);
      }
    }
  };
  if (planes) {
    plane_wall_rows(world, first, last, tally);
    return;
  }
  for (std::size_t i = first; i < last; ++i) row(i, tally);
}

template bool walls_by_plane_passes<2>(const World<2>&, bool, bool);
template bool walls_by_plane_passes<3>(const World<3>&, bool, bool);
#define GEODEM_WALL_ROWS(D, M, E) \
  template void wall_rows<D, M, E>(World<D>&, std::size_t, std::size_t, SlabTally<D>&, bool);
GEODEM_WALL_ROWS(2, false, false)
GEODEM_WALL_ROWS(2, false, true)
GEODEM_WALL_ROWS(2, true, false)
GEODEM_WALL_ROWS(2, true, true)
GEODEM_WALL_ROWS(3, false, false)
GEODEM_WALL_ROWS(3, false, true)
GEODEM_WALL_ROWS(3, true, false)
GEODEM_WALL_ROWS(3, true, true)
#undef GEODEM_WALL_ROWS

}  // namespace geodem
