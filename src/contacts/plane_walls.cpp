// Plane walls in two passes over chunks of up to 64 listed grain-wall pairs:
//   measure  rows in index order, pairs in list order: each pair's overlap; a touching pair
//            takes the chunk's next slot (the slot advances by the outcome, no branch on it),
//            a pair apart ends its history through an integer mask;
//   compute  the touching pairs in list order, exactly as the scalar loop computes them.
// Whether a grain near a wall touches it changes from step to step and is hard to predict;
// a wrong guess discarded the contact computation in flight behind it.
#include "contacts/plane_walls.hpp"

#include <algorithm>
#include <cstdint>

#include "contacts/contact_law.hpp"

namespace geodem {

template <int D>
bool plane_walls_only(const World<D>& world) {
  return std::all_of(world.walls.begin(), world.walls.end(),
                     [](const Wall<D>& w) { return w.kind == WallKind::kPlane; });
}

template <int D>
void plane_wall_rows(World<D>& world, std::size_t first, std::size_t last, SlabTally<D>& t) {
  using Vec = typename Dim<D>::Vec;
  auto& P = world.particles;
  auto& L = world.nlist;
  const double dt = world.dt;
  const auto& walls = world.walls;
  const auto& shares = world.collision_shares.wall;
  const bool dashpots = world.tally_wall_dashpots;
  constexpr int kChunk = 64;
  std::uint32_t grain[kChunk + 1], pair[kChunk + 1];
  double overlap[kChunk + 1];
  auto compute = [&](int count) {
    for (int c = 0; c < count; ++c) {
      const std::uint32_t i = grain[c], k = pair[c], w = L.wall[k];
      const auto& wall = walls[w];
      const double ri = P.radius[i], delta = overlap[c];
      const Vec nrm = -wall.normal;  // from the grain to the wall
      if (delta > world.overlap_limit * ri) [[unlikely]]
        t.note_overlap(i, -1 - static_cast<std::int64_t>(w), delta / ri);
      // The contact point lies on the wall's surface: the lever arm is R - delta.
      const double a = ri - delta;
      const Vec vrel = wall.velocity - (P.vel[i] + Dim<D>::cross(P.angvel[i], a * nrm));
      const PairLaw& law = world.wall_law(P.material[i], w);
      const double r2 = wall_partner_radius(law, ri);
      const double inv_m = shares.empty() ? P.inv_mass[i] : P.inv_mass[i] * shares[k];
      double fn;
      const Vec f =
          contact_force<D>(law, ri, r2, inv_m, nrm, delta, vrel, dt, L.wall_spring[k], fn);
      P.force[i] -= f;
      P.torque[i] -= a * Dim<D>::cross(nrm, f);
      t.wall_force[w] += f;
      const double k_wall = normal_stiffness(law, ri, r2, fn, delta);
      t.wall_stiffness[w] += k_wall;
      const double c_wall = dashpots ? normal_dashpot(law, ri, r2, inv_m, delta) : 0.0;
      t.wall_dashpot[w] += c_wall;
      if (t.exact.on) t.exact.add_wall(w, f, k_wall, c_wall);
    }
  };
  int slot = 0;
  for (std::size_t i = first; i < last; ++i) {
    const std::uint32_t b = L.wall_start[i], e = L.wall_start[i + 1];
    if (b == e) continue;
    const Vec xi = P.pos[i];
    const double ri = P.radius[i];
    for (std::uint32_t k = b; k < e; ++k) {
      const auto& wall = walls[L.wall[k]];
      const double delta = ri - (xi - wall.point).dot(wall.normal);
      // The scalar loop's test: a NaN overlap counts as touching there too.
      const bool touching = !(delta <= 0.0);
      grain[slot] = static_cast<std::uint32_t>(i);
      pair[slot] = k;
      overlap[slot] = delta;
      slot += touching;
      keep_or_clear_spring<D>(L.wall_spring[k], std::uint64_t{0} - std::uint64_t{touching});
      if (slot == kChunk) {
        compute(slot);
        slot = 0;
      }
    }
  }
  compute(slot);
}

template bool plane_walls_only<2>(const World<2>&);
template bool plane_walls_only<3>(const World<3>&);
template void plane_wall_rows<2>(World<2>&, std::size_t, std::size_t, SlabTally<2>&);
template void plane_wall_rows<3>(World<3>&, std::size_t, std::size_t, SlabTally<3>&);

}  // namespace geodem
