#include "study/study_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace geodem {

SeriesAnalysis analyse_series(const std::vector<SizeSample>& runs, int dimension, double tolerance,
                              bool with_scatter) {
  std::map<std::size_t, std::vector<const SizeSample*>> by_count;
  for (const auto& r : runs) by_count[r.count].push_back(&r);
  if (by_count.size() < 2) throw std::invalid_argument("a series needs two grain counts or more");
  SeriesAnalysis a;
  std::vector<double> x, m, sd, c_fit;
  for (const auto& [count, group] : by_count) {
    SizeGroup g;
    g.count = count;
    g.runs = group.size();
    std::vector<double> values, sizes;
    for (const SizeSample* r : group) {
      values.push_back(r->value);
      sizes.push_back(r->d0_over_L);
    }
    g.mean = mean(values);
    g.std = standard_deviation(values);
    g.d0_over_L = mean(sizes);
    a.groups.push_back(g);
    x.push_back(g.d0_over_L);
    m.push_back(g.mean);
    sd.push_back(g.std);
    c_fit.push_back(g.d0_over_L * std::pow(static_cast<double>(count), 1.0 / dimension));
  }
  a.mean_fit = fit_line(x, m);
  a.std_fit = fit_line(x, sd);
  a.extrapolated = a.mean_fit.intercept;
  a.size_constant = mean(c_fit);
  const double ref = std::abs(a.extrapolated);
  for (auto& g : a.groups) {
    g.bias = ref > 0.0 ? (g.mean - a.extrapolated) / ref : 0.0;
    g.bias_fit = ref > 0.0 ? a.mean_fit.slope * g.d0_over_L / ref : 0.0;
    g.scatter = ref > 0.0 ? g.std / ref : 0.0;
    g.scatter_fit = ref > 0.0 ? std::max(0.0, a.std_fit.at(g.d0_over_L)) / ref : 0.0;
  }
  // Fitted error at d0/L = x: |slope| x (+ std intercept + std slope x), relative to
  // the extrapolated value; it grows with x, so the tolerance gives an upper bound on x.
  double rate = std::abs(a.mean_fit.slope), base = 0.0;
  if (with_scatter) {
    rate += a.std_fit.slope;
    base = std::max(0.0, a.std_fit.intercept);
  }
  if (ref > 0.0 && tolerance * ref > base) {
    if (rate > 0.0) {
      a.d0_over_L_for_tolerance = (tolerance * ref - base) / rate;
      a.count_for_tolerance = std::ceil(
          std::pow(a.size_constant / a.d0_over_L_for_tolerance, static_cast<double>(dimension)));
    } else {
      a.d0_over_L_for_tolerance = std::numeric_limits<double>::infinity();
      a.count_for_tolerance = 1.0;
    }
  }
  for (std::size_t i = a.groups.size(); i-- > 0;) {
    const auto& g = a.groups[i];
    const double err = std::abs(g.bias) + (with_scatter ? g.scatter : 0.0);
    if (err > tolerance) break;
    a.smallest_tested_count = g.count;
  }
  return a;
}

RateAnalysis analyse_rates(const std::vector<RateSample>& runs, double tolerance) {
  RateAnalysis a;
  std::vector<double> x, y;
  std::map<double, std::vector<const RateSample*>> by_damping;
  for (const auto& r : runs) {
    x.push_back(r.damping * r.strain_rate);
    y.push_back(r.value);
    by_damping[r.damping].push_back(&r);
  }
  a.fit = fit_line(x, y);
  a.quasi_static = a.fit.intercept;
  a.k = a.fit.slope;
  const double qs = std::abs(a.quasi_static);
  for (const auto& r : runs) a.bias.push_back(qs > 0.0 ? (r.value - a.quasi_static) / qs : 0.0);
  for (const auto& [damping, group] : by_damping) {
    DampingFit d;
    d.damping = damping;
    std::vector<double> rx, ry;
    for (const RateSample* r : group) {
      rx.push_back(r->strain_rate);
      ry.push_back(r->value);
    }
    std::vector<double> distinct = rx;
    std::sort(distinct.begin(), distinct.end());
    if (std::unique(distinct.begin(), distinct.end()) - distinct.begin() >= 2) {
      d.fit = fit_line(rx, ry);
      if (damping > 0.0) d.k = d.fit.slope / damping;
    }
    // From the joint fit: the bias |k| D rate / QS reaches the tolerance at this rate.
    if (damping > 0.0 && a.k != 0.0 && qs > 0.0)
      d.max_rate = tolerance * qs / (std::abs(a.k) * damping);
    a.per_damping.push_back(d);
  }
  return a;
}

}  // namespace geodem
