// The cuts of a decomposed domain moved to balance the ranks' measured work
// (domain/slab_domain.hpp): results do not depend on where the cuts are.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "domain/balanced_cuts.hpp"
#include "domain/slab_domain.hpp"

namespace geodem {

// Each rank's step time since the last window, less its time in messages, spread over its
// grains, binned along x and gathered; every rank then sees the same bins. The cuts move only
// when the work was uneven in `rebalance_persistence` windows in a row (a hiccup of the machine
// in one window moves nothing), and then `rebalance_damping` of the way to equal shares
// (balanced_cuts). The next build migrates the grains.
template <int D>
void SlabDomain<D>::rebalance(const World<D>& world) {
  const auto& P = world.particles;
  const int ranks = comm_->size();
  double work = -comm_seconds_;
  for (double s : world.stage_seconds) work += s;
  const double spent = std::max(work - work_at_rebalance_, 0.0);
  work_at_rebalance_ = work;
  constexpr std::size_t kBins = 1024;
  const double x0 = periodic_ ? 0.0 : grid_lo_.x();
  const double span = periodic_ ? 1.0 : static_cast<double>(grid_dims_[0]) * ghost_width_;
  std::vector<double> bins(kBins, 0.0);
  const std::size_t mine = owned(world);
  const double per_grain = mine > 0 ? spent / static_cast<double>(mine) : 0.0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.flags[i] & kGhost) continue;
    const double b = std::floor((across(P.pos[i]) - x0) / span * static_cast<double>(kBins));
    bins[static_cast<std::size_t>(std::clamp(b, 0.0, static_cast<double>(kBins - 1)))] += per_grain;
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
  // Near an even share the cuts stay: moving them for timing noise costs migrations.
  uneven_windows_ = imbalanced(rank_work, rebalance_tolerance) ? uneven_windows_ + 1 : 0;
  if (uneven_windows_ < std::max(rebalance_persistence, 1)) return;
  uneven_windows_ = 0;
  cuts_ = balanced_cuts(total, cuts_, x0, span, in_cuts(min_slab()), rebalance_damping);
}

// (the class's other members are instantiated in slab_domain.cpp)
template void SlabDomain<2>::rebalance(const World<2>&);
template void SlabDomain<3>::rebalance(const World<3>&);

}  // namespace geodem
