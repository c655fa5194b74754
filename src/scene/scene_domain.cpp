#include "scene/scene_domain.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "base/error.hpp"
#include "distributed/mpi_domain_comm.hpp"
#include "domain/local_comm.hpp"
#include "measure/measurements.hpp"

namespace geodem {

template <int D>
std::shared_ptr<SlabDomain<D>> decompose_world(World<D>& world, const std::string& file,
                                               const DomainCheckpoint<D>* resumed, bool local,
                                               int rebalance_every) {
  try {
    const std::shared_ptr<DomainComm> comm =
        local ? std::make_shared<LocalDomainComm>() : mpi_domain_comm();
    auto domain = SlabDomain<D>::distribute(world, comm, resumed);
    domain->rebalance_every = rebalance_every;
    return domain;
  } catch (const InputError& e) {  // too many ranks for the grains: name the file
    throw InputError(file, 0, "mpirun -n", e.detail());
  }
}

template <int D>
std::shared_ptr<SlabDomain<D>> decompose_scene(const SceneSettings& s, World<D>& world,
                                               const DomainCheckpoint<D>* resumed, bool local,
                                               int rebalance_every) {
  return decompose_world(world, s.file, resumed, local, rebalance_every);
}

namespace {

// What the particle table and the displacements read of a grain (64 bytes in 3D, against the
// 176 of a migrating grain's record: the end of a run of 10^7 grains gathers them all).
template <int D>
struct TableRow {
  typename Dim<D>::Vec pos, vel;
  double radius;
  std::uint32_t id;
  std::uint16_t material;
};

// Every rank's own grains in id order, on every rank (rank 0 only with `root_only`).
template <int D>
std::vector<TableRow<D>> gather_grains(const World<D>& world, SlabDomain<D>& domain,
                                       bool root_only) {
  const auto& P = world.particles;
  std::vector<TableRow<D>> rows;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (!(P.flags[i] & kGhost))
      rows.push_back({P.pos[i], P.vel[i], P.radius[i], P.id[i], P.material[i]});
  Bytes out;
  put_records(out, rows);
  std::vector<TableRow<D>>().swap(rows);
  const Bytes all = root_only ? domain.comm().gather(out) : domain.comm().all_gather(out);
  Bytes().swap(out);
  std::size_t at = 0;
  while (at < all.size()) append_records(all, at, rows);
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return rows;
}

}  // namespace

template <int D>
Particles<D> grains_on_rank0(const World<D>& world, SlabDomain<D>& domain) {
  Particles<D> out;  // (only the arrays the particle table reads)
  const auto rows = gather_grains(world, domain, true);
  out.pos.reserve(rows.size()), out.vel.reserve(rows.size()), out.radius.reserve(rows.size());
  out.id.reserve(rows.size()), out.material.reserve(rows.size());
  for (const auto& g : rows) {
    out.pos.push_back(g.pos), out.vel.push_back(g.vel), out.radius.push_back(g.radius);
    out.id.push_back(g.id), out.material.push_back(g.material);
  }
  out.next_id = world.particles.next_id;
  return out;
}

template <int D>
DomainWorldOnRank0<D>::DomainWorldOnRank0(World<D>& world, SlabDomain<D>* domain,
                                          DomainCheckpoint<D>& saved)
    : world_(world), saved_(saved) {
  if (!domain) return;
  grains_ = domain->checkpoint(world, saved, clumps_);
  broken_bonds_ = broken_bond_count(world);
  if (domain->rank() != 0) return;
  swap();
  swapped_ = true;
}

template <int D>
DomainWorldOnRank0<D>::~DomainWorldOnRank0() {
  if (swapped_) swap();
  saved_ = DomainCheckpoint<D>{};
}

template <int D>
void DomainWorldOnRank0<D>::swap() {
  std::swap(world_.particles, grains_);
  std::swap(world_.clumps, clumps_);
  world_.nlist.swap_rows(rows_);
  std::swap(world_.broken_bonds, broken_bonds_);
}

template <int D>
Particles<D> domain_grains(const World<D>& world) {
  Particles<D> out;  // (centres, radii and ids)
  auto& domain = dynamic_cast<SlabDomain<D>&>(*world.domain);
  for (const auto& g : gather_grains(world, domain, false))
    out.pos.push_back(g.pos), out.radius.push_back(g.radius), out.id.push_back(g.id);
  out.next_id = world.particles.next_id;
  return out;
}

template <int D>
void keep_own_added_grains(World<D>& world, std::size_t first_grain, std::size_t first_clump) {
  dynamic_cast<SlabDomain<D>&>(*world.domain).grains_added(world, first_grain, first_clump);
}

template <int D>
std::vector<typename Dim<D>::Vec> domain_positions_by_id(const World<D>& world,
                                                         SlabDomain<D>& domain) {
  std::vector<typename Dim<D>::Vec> ref(
      world.particles.next_id, Dim<D>::Vec::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (const auto& g : gather_grains(world, domain, false))
    if (g.id < ref.size()) ref[g.id] = g.pos;
  return ref;
}

template std::shared_ptr<SlabDomain<2>> decompose_world<2>(World<2>&, const std::string&,
                                                           const DomainCheckpoint<2>*, bool, int);
template std::shared_ptr<SlabDomain<3>> decompose_world<3>(World<3>&, const std::string&,
                                                           const DomainCheckpoint<3>*, bool, int);
template std::shared_ptr<SlabDomain<2>> decompose_scene<2>(const SceneSettings&, World<2>&,
                                                           const DomainCheckpoint<2>*, bool, int);
template std::shared_ptr<SlabDomain<3>> decompose_scene<3>(const SceneSettings&, World<3>&,
                                                           const DomainCheckpoint<3>*, bool, int);
template Particles<2> grains_on_rank0<2>(const World<2>&, SlabDomain<2>&);
template Particles<3> grains_on_rank0<3>(const World<3>&, SlabDomain<3>&);
template class DomainWorldOnRank0<2>;
template class DomainWorldOnRank0<3>;
template Particles<2> domain_grains<2>(const World<2>&);
template Particles<3> domain_grains<3>(const World<3>&);
template void keep_own_added_grains<2>(World<2>&, std::size_t, std::size_t);
template void keep_own_added_grains<3>(World<3>&, std::size_t, std::size_t);
template std::vector<Dim<2>::Vec> domain_positions_by_id<2>(const World<2>&, SlabDomain<2>&);
template std::vector<Dim<3>::Vec> domain_positions_by_id<3>(const World<3>&, SlabDomain<3>&);

}  // namespace geodem
