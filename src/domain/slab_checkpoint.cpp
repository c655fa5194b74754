// Checkpoints of a decomposed domain (domain/slab_domain.hpp): the whole domain gathered on
// rank 0 as one world in key order, and a run resumed from it on any number of ranks with the
// bits it would have had uninterrupted.
//
// Why the list is rebuilt as the last build made it: a grain's forces are summed in its
// partners' key order, and keys are retaken every sort_interval builds, so the bits depend on
// the steps at which the list is built. The resumed run must build at the same steps as the
// run it continues: its list is made from the positions of the last build (each grain's
// pos_at_build, the walls moved back by their displacement since, a periodic cell's shape
// then), the build count is that
// build's, the walls' displacements since it are kept, and the first step measures the grains'
// (the bound each rank kept on them is its own), so that the list expires when it would have.
#include <algorithm>
#include <limits>
#include <tuple>

#include "broadphase/neighbour_search.hpp"
#include "domain/slab_domain.hpp"

namespace geodem {

template <int D>
Particles<D> SlabDomain<D>::checkpoint(const World<D>& world, DomainCheckpoint<D>& saved,
                                       Clumps<D>& clumps) {
  const auto& P = world.particles;
  std::vector<GrainRecord<D>> grains;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (!(P.flags[i] & kGhost))
      grains.push_back(GrainRecord<D>::of(P, i, key_[i], clump_id(world, i)));
  std::vector<ClumpRecord<D>> own_clumps;
  for (std::size_t c = 0; c < world.clumps.owned(); ++c)
    own_clumps.push_back(ClumpRecord<D>::of(world.clumps, c));
  // The rows' history as records (pairs_ and walls_ carry records between builds: kept aside).
  std::vector<PairRecord<D>> carried_pairs;
  std::vector<WallRecord<D>> carried_walls;
  std::vector<SparRecord<D>> carried_spars;
  pairs_.swap(carried_pairs), walls_.swap(carried_walls), spars_.swap(carried_spars);
  collect_history(world, nullptr);
  Bytes mine;
  put_records(mine, grains);
  put_records(mine, pairs_);
  put_records(mine, walls_);
  put_records(mine, spars_);
  put_records(mine, own_clumps);
  pairs_.swap(carried_pairs), walls_.swap(carried_walls), spars_.swap(carried_spars);
  const Bytes all = comm_->gather(mine);
  Particles<D> out;
  clumps = Clumps<D>{};
  if (comm_->rank() != 0) return out;
  grains.clear(), own_clumps.clear();
  saved.pairs.clear(), saved.walls.clear(), saved.spars.clear();
  std::size_t at = 0;
  while (at < all.size()) {
    append_records(all, at, grains);
    append_records(all, at, saved.pairs);
    append_records(all, at, saved.walls);
    append_records(all, at, saved.spars);
    append_records(all, at, own_clumps);
  }
  std::sort(grains.begin(), grains.end(),
            [](const auto& a, const auto& b) { return a.key < b.key; });
  // A contact across a boundary is listed on both ranks, with the same bits: kept once.
  auto pair_less = [](const auto& x, const auto& y) {
    return std::tie(x.a, x.b) < std::tie(y.a, y.b);
  };
  auto pair_same = [](const auto& x, const auto& y) { return x.a == y.a && x.b == y.b; };
  std::sort(saved.pairs.begin(), saved.pairs.end(), pair_less);
  saved.pairs.erase(std::unique(saved.pairs.begin(), saved.pairs.end(), pair_same),
                    saved.pairs.end());
  std::sort(saved.walls.begin(), saved.walls.end(), [](const auto& x, const auto& y) {
    return std::tie(x.id, x.wall) < std::tie(y.id, y.wall);
  });
  std::sort(saved.spars.begin(), saved.spars.end(), [](const auto& x, const auto& y) {
    return std::tie(x.id, x.element) < std::tie(y.id, y.element);
  });
  out.reserve(grains.size());
  if (!P.orient.empty()) out.orient.reserve(grains.size());
  saved.keys.clear();
  for (const auto& g : grains) {
    g.append_to(out);
    if (!P.orient.empty()) out.orient.push_back(g.orient);
    saved.keys.push_back(g.key);
  }
  out.next_id = P.next_id;
  // The clumps in id order; the members' clump ids become indices.
  clumps.next_id = world.clumps.next_id;
  if (clumped_) {
    ghost_clumps_.clear();
    replace_clumps(out, clumps, own_clumps);
  }
  saved.grid_lo = grid_lo_, saved.grid_dims = grid_dims_, saved.sort_every = sort_every_;
  saved.skin = skin_, saved.ghost_width = ghost_width_, saved.extent = extent_;
  saved.key_block = key_block_;
  return out;
}

template <int D>
void SlabDomain<D>::rebuild_as_saved(World<D>& world) {
  auto& P = world.particles;
  // The positions of the last build, carried through the build's renumbering in pos_at_build.
  std::swap(P.pos, P.pos_at_build);
  std::swap(world.spars.pos, world.spars.pos_at_build);  // the chains' nodes likewise
  const std::vector<Wall<D>> walls = world.walls;        // put back bit for bit below
  for (auto& w : world.walls) w.point -= w.displacement, w.end -= w.displacement;
  const auto h = world.cell.h;  // a periodic cell as it was at that build
  world.cell.h = world.cell.h_at_build;
  const double radius_growth = world.radius_growth;
  const std::uint64_t builds = world.nlist.builds;
  // (the count before that build: keys are retaken from those positions if it retook them)
  if (builds > 0) world.nlist.builds = builds - 1;
  before_build(world);
  std::vector<typename Dim<D>::Vec> now = P.pos_at_build, nodes_now = world.spars.pos_at_build;
  build_neighbour_list(world);  // pos_at_build = the positions of the last build
  P.pos = std::move(now);
  world.spars.pos = std::move(nodes_now);
  world.walls = walls;
  world.cell.h = h;
  // The bound on the grains' displacement since that build is each rank's own (from its
  // grains' speeds) and the checkpoint has rank 0's: the first step measures them instead.
  world.disp_bound = std::numeric_limits<double>::infinity();
  world.radius_growth = radius_growth;
  world.nlist.builds = builds;
  P.force.assign(P.size(), Dim<D>::Vec::Zero());
  P.torque.assign(P.size(), Dim<D>::zero_rot());
}

// (the class's other members are instantiated in slab_domain.cpp)
template Particles<2> SlabDomain<2>::checkpoint(const World<2>&, DomainCheckpoint<2>&, Clumps<2>&);
template Particles<3> SlabDomain<3>::checkpoint(const World<3>&, DomainCheckpoint<3>&, Clumps<3>&);
template void SlabDomain<2>::rebuild_as_saved(World<2>&);
template void SlabDomain<3>::rebuild_as_saved(World<3>&);

}  // namespace geodem
