// The cuts of a decomposed domain moved to balance the ranks' work, modelled or measured
// (domain/slab_domain.hpp): results do not depend on where the cuts are.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "base/cpu_time.hpp"
#include "domain/balanced_cuts.hpp"
#include "domain/slab_domain.hpp"

namespace geodem {

// A grain's work in the model: 1 for its integration and search, and kPairWork for each
// contact pair, wall pair or spar-element pair its rank computes for it (a pair of two owned
// grains half to each, a pair with a ghost wholly to the owned grain). kPairWork from B2's
// settled bed on one process: the force stage 64 % of a step, the integration and search
// 36 %, at 3.5 listed pairs a grain (1.77 / 3.5 = 0.5).
constexpr double kPairWork = 0.5;

template <int D>
std::vector<double> SlabDomain<D>::modelled_work(const World<D>& world) const {
  const auto& P = world.particles;
  const auto& L = world.nlist;
  std::vector<double> work(P.size(), 1.0);
  if (L.start.size() != P.size() + 1) return work;
  for (std::size_t i = 0; i < P.size(); ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::size_t j = L.other[k];
      const bool gi = P.flags[i] & kGhost, gj = P.flags[j] & kGhost;
      const double share = gi || gj ? kPairWork : 0.5 * kPairWork;
      if (!gi) work[i] += share;
      if (!gj) work[j] += share;
    }
    if (L.wall_start.size() == P.size() + 1)
      work[i] += kPairWork * static_cast<double>(L.wall_start[i + 1] - L.wall_start[i]);
    if (L.spar_start.size() == P.size() + 1)
      work[i] += kPairWork * static_cast<double>(L.spar_start[i + 1] - L.spar_start[i]);
  }
  return work;
}

// A grain's work measured: its rank's thread CPU time since the last window (less that in
// messages), shared evenly among the rank's grains.
template <int D>
std::vector<double> SlabDomain<D>::measured_work(const World<D>& world) {
  const double cpu = thread_cpu_seconds() - comm_cpu_seconds_;
  const bool first = std::isnan(work_at_rebalance_);  // a copy's first window: no measure yet
  const double spent = first ? 0.0 : std::max(cpu - work_at_rebalance_, 0.0);
  work_at_rebalance_ = cpu;
  const std::size_t mine = owned(world);
  return std::vector<double>(world.particles.size(),
                             mine > 0 ? spent / static_cast<double>(mine) : 0.0);
}

// Each grain's work (modelled from its contacts, or measured), binned along x and gathered;
// every rank then sees the same bins. The cuts move when the work was uneven in
// `rebalance_persistence` windows in a row, `rebalance_damping` of the way to equal shares
// (balanced_cuts). The next build migrates the grains.
template <int D>
void SlabDomain<D>::rebalance(const World<D>& world) {
  const auto& P = world.particles;
  const int ranks = comm_->size();
  constexpr std::size_t kBins = 1024;
  const double x0 = periodic_ ? 0.0 : grid_lo_.x();
  const double span = periodic_ ? 1.0 : static_cast<double>(grid_dims_[0]) * ghost_width_;
  std::vector<double> bins(kBins, 0.0);
  const std::vector<double> work = rebalance_on_time ? measured_work(world) : modelled_work(world);
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.flags[i] & kGhost) continue;
    const double b = std::floor((across(P.pos[i]) - x0) / span * static_cast<double>(kBins));
    bins[static_cast<std::size_t>(std::clamp(b, 0.0, static_cast<double>(kBins - 1)))] += work[i];
  }
  Bytes out(kBins * sizeof(double));
  std::memcpy(out.data(), bins.data(), out.size());
  const Bytes all = comm_->all_gather(out);
  std::vector<double> total(kBins, 0.0), rank_work(static_cast<std::size_t>(ranks), 0.0);
  for (int r = 0; r < ranks; ++r) {  // in rank order: the same sums on every rank
    for (std::size_t b = 0; b < kBins; ++b) {
      double v;
      std::memcpy(&v, all.data() + (static_cast<std::size_t>(r) * kBins + b) * sizeof v, sizeof v);
      total[b] += v;
      rank_work[static_cast<std::size_t>(r)] += v;
    }
  }
  if (const double share = busiest_share(rank_work); share > 0.0) work_imbalance_ = share;
  // Near an even share the cuts stay: moving them for little costs migrations.
  uneven_windows_ = imbalanced(rank_work, rebalance_tolerance) ? uneven_windows_ + 1 : 0;
  if (uneven_windows_ < std::max(rebalance_persistence, 1)) return;
  uneven_windows_ = 0;
  const std::vector<double> old = cuts_;
  cuts_ = balanced_cuts(total, cuts_, x0, span, in_cuts(min_slab()), rebalance_damping);
  if (cuts_ != old) ++cut_moves_;
}

// (the class's other members are instantiated in slab_domain.cpp)
template void SlabDomain<2>::rebalance(const World<2>&);
template void SlabDomain<3>::rebalance(const World<3>&);

}  // namespace geodem
