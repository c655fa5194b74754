// The statistics of the representativeness and rate studies, as pure functions over
// the runs' results, so that they are tested on synthetic data (docs/studies.md).
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "study/linear_fit.hpp"

namespace geodem {

// --- Representativeness (kind = "series") --------------------------------------------

struct SizeSample {
  std::size_t count = 0;   // grains in the sample
  double d0_over_L = 0.0;  // mean grain size over sample height
  double value = 0.0;      // the studied result (peak stress...)
};

struct SizeGroup {
  std::size_t count = 0, runs = 0;
  double d0_over_L = 0.0;  // mean over the group's runs
  double mean = 0.0, std = 0.0;
  double bias = 0.0;         // (mean - extrapolated) / extrapolated, measured
  double bias_fit = 0.0;     // slope * d0/L / extrapolated, from the fit of the means
  double scatter = 0.0;      // std / extrapolated
  double scatter_fit = 0.0;  // from the fit of the standard deviations
};

struct SeriesAnalysis {
  std::vector<SizeGroup> groups;  // by increasing count
  LinearFit mean_fit, std_fit;    // against d0/L
  double extrapolated = 0.0;      // mean for an infinite sample (d0/L -> 0)
  // d0/L = size_constant * count^(-1/D): the sample's shape, fitted to the runs.
  double size_constant = 0.0;
  // Largest d0/L and smallest count whose fitted bias (plus one fitted standard
  // deviation with `with_scatter`) stays within the tolerance; infinite when no
  // sample size does.
  double d0_over_L_for_tolerance = 0.0;
  double count_for_tolerance = std::numeric_limits<double>::infinity();
  // Smallest tested count whose measured |bias| (+ scatter) is within the tolerance
  // for it and every larger count; 0 when none.
  std::size_t smallest_tested_count = 0;
};

// Needs two counts or more. `dimension` sets the count -> d0/L law.
SeriesAnalysis analyse_series(const std::vector<SizeSample>& runs, int dimension, double tolerance,
                              bool with_scatter);

// --- Strain-rate effects (kind = "rate_study") ---------------------------------------

struct RateSample {
  double strain_rate = 0.0, damping = 0.0, value = 0.0;
};

struct DampingFit {
  double damping = 0.0;
  LinearFit fit;   // value against strain rate, this damping only (needs two rates)
  double k = 0.0;  // slope / damping (0 without damping)
  // Largest strain rate whose rate bias k D rate / QS stays within the tolerance.
  double max_rate = std::numeric_limits<double>::infinity();
};

struct RateAnalysis {
  LinearFit fit;  // value = quasi_static + k * (damping * strain_rate)
  double quasi_static = 0.0, k = 0.0;
  std::vector<DampingFit> per_damping;  // by increasing damping
  std::vector<double> bias;             // per run: (value - QS) / QS
};

RateAnalysis analyse_rates(const std::vector<RateSample>& runs, double tolerance);

}  // namespace geodem
