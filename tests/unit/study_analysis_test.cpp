// The fits and statistics of the studies, on synthetic data with known answers
// (docs/studies.md): straight lines with and without noise, a representativeness series
// whose bias is exactly linear in d0/L, and a rate study that follows
// sigma = sigma_QS + k D rate.
#include <gtest/gtest.h>

#include <cmath>

#include "base/random.hpp"
#include "study/linear_fit.hpp"
#include "study/study_analysis.hpp"

namespace geodem {
namespace {

TEST(LinearFit, RecoversAnExactLine) {
  const std::vector<double> x = {0.01, 0.02, 0.05, 0.1};
  std::vector<double> y;
  for (double v : x) y.push_back(3.2e4 - 1.5e5 * v);
  const LinearFit f = fit_line(x, y);
  EXPECT_NEAR(f.intercept, 3.2e4, 1e-9 * 3.2e4);
  EXPECT_NEAR(f.slope, -1.5e5, 1e-9 * 1.5e5);
  EXPECT_NEAR(f.r2, 1.0, 1e-12);
  EXPECT_NEAR(f.slope_error, 0.0, 1e-6);
}

TEST(LinearFit, StandardErrorsMatchTheScatterOfNoisyLines) {
  // 2000 noisy data sets of the same line: the spread of the fitted slopes and
  // intercepts equals the standard errors the fit reports (to the sampling error of
  // 2000 draws, about 2 %: 5 % allowed).
  Random rng(7);
  const std::vector<double> x = {1, 2, 3, 4, 5, 6, 7, 8};
  const double sigma = 0.3;
  std::vector<double> slopes, intercepts, slope_err, intercept_err;
  for (int k = 0; k < 2000; ++k) {
    std::vector<double> y;
    for (double v : x) {
      // Box-Muller normal deviates.
      const double u1 = rng.uniform(1e-12, 1.0), u2 = rng.uniform(0.0, 1.0);
      y.push_back(1.0 + 0.5 * v +
                  sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2));
    }
    const LinearFit f = fit_line(x, y);
    slopes.push_back(f.slope);
    intercepts.push_back(f.intercept);
    slope_err.push_back(f.slope_error);
    intercept_err.push_back(f.intercept_error);
  }
  EXPECT_NEAR(mean(slopes), 0.5, 0.01);
  EXPECT_NEAR(mean(intercepts), 1.0, 0.03);
  // Mean reported error vs the observed spread (the RMS of the error estimates is the
  // unbiased one).
  auto rms = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double e : v) s += e * e;
    return std::sqrt(s / static_cast<double>(v.size()));
  };
  EXPECT_NEAR(rms(slope_err) / standard_deviation(slopes), 1.0, 0.05);
  EXPECT_NEAR(rms(intercept_err) / standard_deviation(intercepts), 1.0, 0.05);
}

TEST(LinearFit, RejectsDegenerateInput) {
  EXPECT_THROW(fit_line({1.0}, {2.0}), std::invalid_argument);
  EXPECT_THROW(fit_line({1.0, 1.0}, {2.0, 3.0}), std::invalid_argument);
}

TEST(Statistics, MeanAndSampleStandardDeviation) {
  EXPECT_DOUBLE_EQ(mean({1.0, 2.0, 6.0}), 3.0);
  EXPECT_DOUBLE_EQ(standard_deviation({1.0, 2.0, 6.0}), std::sqrt(7.0));
  EXPECT_DOUBLE_EQ(standard_deviation({4.0}), 0.0);
}

// A 2D series: d0/L = C / sqrt(N); each seed's value = V (1 + a d0/L) + e_k s(d0/L) with
// deviations e_k = (-1, 0, 1) (sample std 1) and s linear in d0/L: the analysis must give
// back V, a V, the std line and the count where the bias a d0/L reaches the tolerance.
TEST(SeriesAnalysis, RecoversBiasScatterAndTheCountForATolerance) {
  const double V = 1.0e5, a = 2.0, C = 1.6, s0 = 500.0, s1 = 4.0e4;
  std::vector<SizeSample> runs;
  for (std::size_t n : {500u, 1000u, 2000u, 4000u, 8000u}) {
    const double x = C / std::sqrt(static_cast<double>(n));
    for (double e : {-1.0, 0.0, 1.0}) runs.push_back({n, x, V * (1.0 + a * x) + e * (s0 + s1 * x)});
  }
  const double tol = 0.02;
  const SeriesAnalysis r = analyse_series(runs, 2, tol, false);
  ASSERT_EQ(r.groups.size(), 5u);
  EXPECT_NEAR(r.extrapolated, V, 1e-9 * V);
  EXPECT_NEAR(r.mean_fit.slope, a * V, 1e-9 * a * V);
  EXPECT_NEAR(r.std_fit.intercept, s0, 1e-6 * s0);
  EXPECT_NEAR(r.std_fit.slope, s1, 1e-9 * s1);
  EXPECT_NEAR(r.size_constant, C, 1e-12);
  const double x500 = C / std::sqrt(500.0);
  EXPECT_NEAR(r.groups[0].bias, a * x500, 1e-9);
  EXPECT_NEAR(r.groups[0].bias_fit, a * x500, 1e-9);
  EXPECT_NEAR(r.groups[0].scatter, (s0 + s1 * x500) / V, 1e-9);
  // a x = tol at x = tol / a, N = (C a / tol)^2 = 25,600.
  EXPECT_NEAR(r.d0_over_L_for_tolerance, tol / a, 1e-12);
  EXPECT_NEAR(r.count_for_tolerance, std::ceil(std::pow(C * a / tol, 2.0)), 1.0);
  // Measured biases 2 C / sqrt(N): 0.143 ... 0.036, all above 2 %.
  EXPECT_EQ(r.smallest_tested_count, 0u);
  // With the scatter: |bias| + std/V = tol at x = (tol - s0/V) / (a + s1/V).
  const SeriesAnalysis w = analyse_series(runs, 2, tol, true);
  EXPECT_NEAR(w.d0_over_L_for_tolerance, (tol - s0 / V) / (a + s1 / V), 1e-12);
  // A tolerance of 10 % holds from 2,000 grains on (bias 0.0716 there, 0.101 at 1,000).
  EXPECT_EQ(analyse_series(runs, 2, 0.10, false).smallest_tested_count, 2000u);
}

TEST(SeriesAnalysis, ThreeDimensionalCountLaw) {
  const double C = 1.2, V = 50.0, a = -1.0;
  std::vector<SizeSample> runs;
  for (std::size_t n : {1000u, 8000u}) {
    const double x = C / std::cbrt(static_cast<double>(n));
    runs.push_back({n, x, V * (1.0 + a * x)});
  }
  const SeriesAnalysis r = analyse_series(runs, 3, 0.01, false);
  EXPECT_NEAR(r.extrapolated, V, 1e-9 * V);
  EXPECT_NEAR(r.count_for_tolerance, std::ceil(std::pow(C / 0.01, 3.0)), 2.0);
}

TEST(SeriesAnalysis, NeedsTwoCounts) {
  EXPECT_THROW(analyse_series({{100, 0.1, 1.0}, {100, 0.1, 2.0}}, 2, 0.05, false),
               std::invalid_argument);
}

// sigma = QS + k D rate exactly, over three rates and three damping values: the fit
// returns QS and k, each damping's slope is k D, and the largest rate within a 2 % bias
// is 0.02 QS / (k D).
TEST(RateAnalysis, RecoversTheQuasiStaticLimitAndTheRateBound) {
  const double QS = 8.0e4, k = 2.5e6;
  std::vector<RateSample> runs;
  for (double rate : {0.005, 0.02, 0.08})
    for (double D : {0.05, 0.2, 0.7}) runs.push_back({rate, D, QS + k * D * rate});
  const RateAnalysis r = analyse_rates(runs, 0.02);
  EXPECT_NEAR(r.quasi_static, QS, 1e-9 * QS);
  EXPECT_NEAR(r.k, k, 1e-9 * k);
  EXPECT_NEAR(r.fit.r2, 1.0, 1e-12);
  ASSERT_EQ(r.per_damping.size(), 3u);
  for (const auto& d : r.per_damping) {
    EXPECT_NEAR(d.fit.slope, k * d.damping, 1e-6 * k);
    EXPECT_NEAR(d.k, k, 1e-6 * k);
    EXPECT_NEAR(d.max_rate, 0.02 * QS / (k * d.damping), 1e-9);
  }
  EXPECT_NEAR(r.bias[8], k * 0.7 * 0.08 / QS, 1e-12);
}

}  // namespace
}  // namespace geodem
