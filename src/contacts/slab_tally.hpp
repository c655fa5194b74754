// The sums one slab of the contact force stage adds to the world's (contacts/contact_forces.cpp),
// shared by its scalar and batched pair loops.
#pragma once

#include <cstdint>
#include <vector>

#include "base/exact_sum.hpp"
#include "world/world.hpp"

namespace geodem {

// A decomposed world's sums (World::domain), taken exactly so that they do not depend on how
// the grains are shared between ranks (docs/parallel.md): per wall its force (D components),
// stiffness and dashpot; on measuring steps the contact statistics, each contact counted on
// the rank that owns the first grain of its row. A periodic cell's sum of d f^T and its
// stiffness every step: d f^T as the owned grains' x F^T (a clump member's x its clump's
// centre) plus each imaged contact's shift f^T, counted like the statistics. Only the
// symmetric part is summed (the cell's stress is that part), D (D + 1) / 2 sums; the
// stiffness is summed in floating point along each row (the same on every rank: a row's
// contacts and their order do not depend on the decomposition), and the row's sum exactly.
template <int D>
struct ExactTally {
  using Vec = typename Dim<D>::Vec;
  static constexpr std::size_t kPerWall = D + 2, kStats = D * D + 4, kSym = D * (D + 1) / 2;
  static constexpr std::size_t kCell = kSym + D;
  bool on = false;
  std::vector<ExactSum> wall, stats;  // stats: fabric (row-major), |f|, energy, counts
  std::vector<ExactSum> cell;         // periodic cell: sym(d f^T) (a <= b), then stiffness

  void reset(bool domain, std::size_t walls, bool measure, bool periodic) {
    on = domain;
    wall.assign(on ? walls * kPerWall : 0, ExactSum{});
    stats.assign(on && measure ? kStats : 0, ExactSum{});
    cell.assign(on && periodic ? kCell : 0, ExactSum{});
    row_ = kNoRow, row_stiffness_ = Vec::Zero();
  }
  // sym(x f^T) into the cell's sum.
  void add_cell_fabric(const Vec& x, const Vec& f) {
    std::size_t k = 0;
    for (int a = 0; a < D; ++a) {
      cell[k++].add(x[a] * f[a]);
      for (int b = a + 1; b < D; ++b) cell[k++].add(0.5 * (x[a] * f[b] + x[b] * f[a]));
    }
  }
  // Row `row`'s contact stiffness k (rows in turn; finish_rows() after the last).
  void add_cell_stiffness(std::size_t row, const Vec& k) {
    if (row != row_) {
      finish_rows();
      row_ = row;
    }
    row_stiffness_ += k;
  }
  void finish_rows() {
    if (row_ != kNoRow)
      for (int a = 0; a < D; ++a) cell[kSym + static_cast<std::size_t>(a)].add(row_stiffness_[a]);
    row_ = kNoRow, row_stiffness_ = Vec::Zero();
  }
  // The cell's sums as the world holds them: d f^T (symmetric) and the stiffness.
  static void read_cell(const ExactSum* sums, typename Dim<D>::Tensor& fabric, Vec& stiffness) {
    std::size_t k = 0;
    for (int a = 0; a < D; ++a)
      for (int b = a; b < D; ++b) fabric(a, b) = fabric(b, a) = sums[k++].value();
    for (int a = 0; a < D; ++a) stiffness[a] = sums[kSym + static_cast<std::size_t>(a)].value();
  }

  void add_wall(std::size_t w, const Vec& f, double stiffness, double dashpot) {
    for (int a = 0; a < D; ++a) wall[w * kPerWall + static_cast<std::size_t>(a)].add(f[a]);
    wall[w * kPerWall + D].add(stiffness);
    wall[w * kPerWall + D + 1].add(dashpot);
  }
  // d: the branch (or lever) the stress sums d f^T over.
  void add_contact(const Vec& d, const Vec& f, double energy, bool with_wall) {
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) stats[static_cast<std::size_t>(a * D + b)].add(d[a] * f[b]);
    stats[D * D].add(f.norm());
    stats[D * D + 1].add(energy);
    stats[D * D + (with_wall ? 3 : 2)].add(1.0);
  }

 private:
  static constexpr std::size_t kNoRow = ~std::size_t{0};
  std::size_t row_ = kNoRow;  // the row whose stiffness is being summed
  Vec row_stiffness_ = Vec::Zero();
};

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
  ExactTally<D> exact;

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
