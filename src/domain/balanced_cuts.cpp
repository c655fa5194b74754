#include "domain/balanced_cuts.hpp"

#include <algorithm>

namespace geodem {

std::vector<double> balanced_cuts(const std::vector<double>& work, const std::vector<double>& old,
                                  double x0, double span, double thinnest, double damping) {
  std::vector<double> cuts = old;
  double sum = 0.0;
  for (double v : work) sum += v;
  if (!(sum > 0.0) || old.size() < 3) return cuts;
  const std::size_t ranks = old.size() - 1, bins = work.size();
  double below = 0.0;  // the work in bins [0, b)
  std::size_t b = 0;
  for (std::size_t q = 1; q < ranks; ++q) {
    const double target = sum * static_cast<double>(q) / static_cast<double>(ranks);
    while (b < bins && below + work[b] < target) below += work[b++];
    const double inside = b < bins && work[b] > 0.0 ? (target - below) / work[b] : 0.0;
    const double even = x0 + span * (static_cast<double>(b) + inside) / static_cast<double>(bins);
    double cut = old[q] + damping * (even - old[q]);
    const double lo = std::max(old[q - 1], cuts[q - 1]) + thinnest, hi = old[q + 1] - thinnest;
    cut = std::min(std::max(cut, lo), hi);
    cuts[q] = lo <= hi ? cut : old[q];
  }
  return cuts;
}

double busiest_share(const std::vector<double>& rank_work) {
  double sum = 0.0, busiest = 0.0;
  for (double w : rank_work) sum += w, busiest = std::max(busiest, w);
  if (!(sum > 0.0)) return 0.0;
  return busiest * static_cast<double>(rank_work.size()) / sum;
}

bool imbalanced(const std::vector<double>& rank_work, double tolerance) {
  return busiest_share(rank_work) > 1.0 + tolerance;
}

}  // namespace geodem
