// The cuts of a decomposed domain moved to balance the ranks' measured work
// (domain/slab_domain.hpp): results do not depend on where the cuts are.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "domain/slab_domain.hpp"

namespace geodem {

// New cuts: each rank's step time since the last move, less its time in messages, spread over
// its grains, binned along x and gathered; every rank then cuts the same histogram at equal
// shares. A cut moves at most to a ghost width from its neighbours' old cuts, so that a grain
// changes ranks by one at most, and inner slabs stay a ghost width across.
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
  std::vector<double> total(kBins, 0.0);
  double slowest = 0.0;
  for (int r = 0; r < ranks; ++r) {  // in rank order: the same sums on every rank
    double rank_work = 0.0;
    for (std::size_t b = 0; b < kBins; ++b) {
      double v;
      std::memcpy(&v, all.data() + (static_cast<std::size_t>(r) * kBins + b) * sizeof v, sizeof v);
      total[b] += v;
      rank_work += v;
    }
    slowest = std::max(slowest, rank_work);
  }
  double sum = 0.0;
  for (double v : total) sum += v;
  // Near an even share the cuts stay: moving them for timing noise costs migrations.
  if (!(sum > 0.0) || slowest <= (1.0 + rebalance_tolerance) * sum / ranks) return;
  const std::vector<double> old = cuts_;
  double cumulative = 0.0;
  std::size_t b = 0;
  for (int q = 1; q < ranks; ++q) {
    const double target = sum * q / ranks;
    while (b < kBins && cumulative + total[b] < target) cumulative += total[b++];
    const double inside = b < kBins && total[b] > 0.0 ? (target - cumulative) / total[b] : 0.0;
    double cut = x0 + span * (static_cast<double>(b) + inside) / static_cast<double>(kBins);
    const auto uq = static_cast<std::size_t>(q);
    const double thinnest = in_cuts(min_slab());
    double lo = old[uq - 1] + thinnest, hi = old[uq + 1] - thinnest;
    if (q > 1) lo = std::max(lo, cuts_[uq - 1] + thinnest);
    cut = std::min(std::max(cut, lo), hi);
    cuts_[uq] = lo <= hi ? cut : old[uq];
  }
}

// (the class's other members are instantiated in slab_domain.cpp)
template void SlabDomain<2>::rebalance(const World<2>&);
template void SlabDomain<3>::rebalance(const World<3>&);

}  // namespace geodem
