#include "contacts/bonds.hpp"

#include <algorithm>

#include "broadphase/neighbour_search.hpp"

namespace geodem {

template <int D>
std::size_t create_bonds(World<D>& world, double gap_tolerance) {
  world.update_contact_extras();
  if (!world.contact_extras) return 0;
  auto& L = world.nlist;
  const auto& P = world.particles;
  bool build = world.rebuild_needed || L.start.size() != P.size() + 1 ||
               L.extra.size() != L.other.size() || L.wall_extra.size() != L.wall.size();
  if (world.domain) build = world.domain->any_rank(build);  // (every rank builds together)
  if (build) {
    if (world.domain) world.domain->before_build(world);
    build_neighbour_list(world);
  }
  std::size_t created = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    // A decomposed world: a pair with a ghost is listed on both ranks, in the row of the grain
    // with the smaller key on both; the rank that owns that grain counts it.
    const bool counts = !world.domain || !(P.flags[i] & kGhost);
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::uint32_t j = L.other[k];
      if (!world.pair_law(P.material[i], P.material[j]).cohesive() || L.extra[k].bonded) continue;
      const double gap = world.branch(i, j, k).norm() - P.radius[i] - P.radius[j];
      // 1e-12: grains placed touching may be apart by rounding.
      if (gap > (gap_tolerance + 1e-12) * std::min(P.radius[i], P.radius[j])) continue;
      L.extra[k].bonded = 1;
      if (counts) ++created;
    }
  }
  if (world.domain) created = world.domain->count_over_ranks(created);
  return created;
}

template std::size_t create_bonds<2>(World<2>&, double);
template std::size_t create_bonds<3>(World<3>&, double);

}  // namespace geodem
