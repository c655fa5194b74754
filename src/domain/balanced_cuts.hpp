// Where the cuts between slabs go for equal work (domain/slab_rebalance.cpp), apart from the
// domain so that the arithmetic is tested on its own: measured times are never the same twice.
#pragma once

#include <vector>

namespace geodem {

// `work` is the whole domain's work binned along [x0, x0 + span) in equal bins; `old` the
// present cuts (ranks + 1 values; the ends stay). Each inner cut goes to where the work below
// it is its rank's equal share, then only `damping` of the way there from where it is (1: all
// the way; 0.5 halves a move made on a noisy measure and approaches a steady target without
// passing it), and at least `thinnest` from its neighbours' old cuts and from the new cut
// below it, so that a grain changes ranks by one at most and no slab falls under the ghost
// width; a cut with no room for that stays. No work at all: the cuts stay.
std::vector<double> balanced_cuts(const std::vector<double>& work, const std::vector<double>& old,
                                  double x0, double span, double thinnest, double damping);

// The busiest rank's work over an even share of the total (1: balanced; 0 without work).
double busiest_share(const std::vector<double>& rank_work);

// Whether a rank is slower than an even share of the work by more than `tolerance`, from each
// rank's work (a rank's share of the total, not its time alone, decides).
bool imbalanced(const std::vector<double>& rank_work, double tolerance);

}  // namespace geodem
