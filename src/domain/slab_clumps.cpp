// A decomposed domain's clumps (domain/slab_domain.hpp): a clump belongs to the rank of its
// centre, with all its members, so that its resultant is summed where it is integrated. Beside
// its own clumps a rank holds a ghost clump for each clump that has ghost members here: it only
// names the body those members belong to (the collision shares count the contacts between two
// bodies, and must count the same on both ranks of a contact across a boundary).
#include <algorithm>
#include <string>

#include "domain/slab_domain.hpp"

namespace geodem {

template <int D>
void SlabDomain<D>::replace_clumps(Particles<D>& P, Clumps<D>& C,
                                   std::vector<ClumpRecord<D>>& owned) {
  auto by_id = [](const auto& a, const auto& b) { return a.id < b.id; };
  auto same_id = [](const auto& a, const auto& b) { return a.id == b.id; };
  std::sort(owned.begin(), owned.end(), by_id);
  std::sort(ghost_clumps_.begin(), ghost_clumps_.end(), by_id);
  ghost_clumps_.erase(std::unique(ghost_clumps_.begin(), ghost_clumps_.end(), same_id),
                      ghost_clumps_.end());
  Clumps<D> fresh;
  fresh.next_id = C.next_id;
  std::uint32_t ids = 0;
  for (const auto* list : {&owned, &ghost_clumps_})
    for (const auto& r : *list) {
      r.append_to(fresh);
      ids = std::max(ids, r.id + 1);
    }
  fresh.ghosts = ghost_clumps_.size();
  std::vector<std::uint32_t> index(ids, kNoClump);
  for (std::size_t c = 0; c < fresh.size(); ++c) index[fresh.id[c]] = static_cast<std::uint32_t>(c);
  for (std::size_t i = 0; i < P.clump.size(); ++i) {
    const std::uint32_t id = P.clump[i];
    if (id == kNoClump) continue;
    if (id >= ids || index[id] == kNoClump)
      throw std::runtime_error("grain " + std::to_string(P.id[i]) + " of clump " +
                               std::to_string(id) + " arrived without its clump");
    P.clump[i] = index[id];
  }
  C = std::move(fresh);
  std::vector<ClumpRecord<D>>().swap(ghost_clumps_);
}

// (the class's other members are instantiated in slab_domain.cpp)
template void SlabDomain<2>::replace_clumps(Particles<2>&, Clumps<2>&,
                                            std::vector<ClumpRecord<2>>&);
template void SlabDomain<3>::replace_clumps(Particles<3>&, Clumps<3>&,
                                            std::vector<ClumpRecord<3>>&);

}  // namespace geodem
