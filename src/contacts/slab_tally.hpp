// The sums one slab of the contact force stage adds to the world's (contacts/contact_forces.cpp),
// shared by its scalar and batched pair loops.
#pragma once

#include <cstdint>
#include <vector>

#include "world/world.hpp"

namespace geodem {

// What one slab adds to the world's sums.
template <int D>
struct SlabTally {
  using Vec = typename Dim<D>::Vec;
  ContactStats<D> stats;
  std::uint64_t broken_bonds = 0;
  std::int64_t overlap_offender = -1, overlap_partner = -1;
  double overlap_ratio = 0.0;
  std::vector<Vec> wall_force;  // per wall
  std::vector<double> wall_stiffness;
  std::vector<double> wall_dashpot;
  Vec cell_stiffness = Vec::Zero();  // periodic cell: sum of kn (d_k n_k)^2
  typename Dim<D>::Tensor cell_fabric = Dim<D>::Tensor::Zero();  // periodic cell: sum of d f^T

  void note_overlap(std::size_t i, std::int64_t partner, double ratio) {
    if (overlap_offender >= 0) return;
    overlap_offender = static_cast<std::int64_t>(i);
    overlap_partner = partner;
    overlap_ratio = ratio;
  }
};

template <int D>
void add_stats(ContactStats<D>& a, const ContactStats<D>& b) {
  a.fabric_stress += b.fabric_stress;
  a.sum_force += b.sum_force;
  a.contacts += b.contacts;
  a.wall_contacts += b.wall_contacts;
  a.spar_contacts += b.spar_contacts;
  a.elastic_energy += b.elastic_energy;
}

// How the periodic cell's sum of d f^T over contacts is taken. Per contact it is a tensor
// update in the pair loop; in 3D its nine sums do not fit in the registers beside the loop's
// own state and cost 12 % of a step (20,000 spheres). There it is summed over grains instead,
// as x F^T with F each grain's total contact force, plus the image offsets' part per contact
// (cell_fabric_of_grains). In 2D the per-contact update costs nothing measurable and is kept.
template <int D>
constexpr bool kFabricByGrain = D == 3;

}  // namespace geodem
