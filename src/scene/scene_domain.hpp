// A scene run over the ranks of mpirun as one model (docs/parallel.md): every rank builds the
// whole world from the scenario (the same seed gives the same grains), then keeps its slab of
// it (domain/slab_domain.hpp). Rank 0 writes the history and the summary from reductions every
// rank computes; the final particle table is gathered to it, and each rank writes its own piece
// of the VTK frames.
#pragma once

#include <memory>

#include "domain/slab_domain.hpp"
#include "io/run_output.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

// Decomposes the world over the ranks of MPI_COMM_WORLD (`resumed`: a world loaded from a
// decomposed run's checkpoint, SlabDomain::distribute); throws InputError for slabs thinner
// than the ghost width.
// With `local`: a domain of one rank in this process, without MPI. `rebalance_every`:
// SlabDomain::rebalance_every (RunOptions, --rebalance).
// The same for any world (a lab test's sample); an InputError names `file` and "mpirun -n".
template <int D>
std::shared_ptr<SlabDomain<D>> decompose_world(World<D>& world, const std::string& file,
                                               const DomainCheckpoint<D>* resumed, bool local,
                                               int rebalance_every);
template <int D>
std::shared_ptr<SlabDomain<D>> decompose_scene(const SceneSettings& s, World<D>& world,
                                               const DomainCheckpoint<D>* resumed, bool local,
                                               int rebalance_every);

// For a checkpoint of a decomposed run (all ranks make one): while it lives, rank 0's world
// holds the whole domain's grains in key order, its clumps in id order, an empty neighbour list
// and the domain's count of broken bonds, and `saved` the keys and contact history
// (SlabDomain::checkpoint); then the rank's own state comes back. Without a domain it does nothing.
template <int D>
class DomainWorldOnRank0 {
 public:
  DomainWorldOnRank0(World<D>& world, SlabDomain<D>* domain, DomainCheckpoint<D>& saved);
  ~DomainWorldOnRank0();
  DomainWorldOnRank0(const DomainWorldOnRank0&) = delete;
  DomainWorldOnRank0& operator=(const DomainWorldOnRank0&) = delete;

 private:
  void swap();
  World<D>& world_;
  DomainCheckpoint<D>& saved_;
  bool swapped_ = false;
  Particles<D> grains_;
  Clumps<D> clumps_;
  NeighbourList<D> rows_;
  std::uint64_t broken_bonds_ = 0;
};

// Every rank's own grains in id order, on rank 0 (the others get none): for the particle table,
// whose arrays alone are filled (id, position, radius, velocity, material).
template <int D>
Particles<D> grains_on_rank0(const World<D>& world, SlabDomain<D>& domain);

// A stage's cloud in a decomposed world: every rank places it alike, clear of the whole
// domain's grains (`domain_grains`: every rank's own grains, centres, radii and ids, in id order,
// on every rank), then keeps its own new grains (SlabDomain::grains_added).
template <int D>
Particles<D> domain_grains(const World<D>& world);
template <int D>
void keep_own_added_grains(World<D>& world, std::size_t first_grain, std::size_t first_clump);

// Positions of every grain of the domain by id (measure/displacement.hpp), on every rank.
template <int D>
std::vector<typename Dim<D>::Vec> domain_positions_by_id(const World<D>& world,
                                                         SlabDomain<D>& domain);

}  // namespace geodem
