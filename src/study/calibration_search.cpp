#include "study/calibration_search.hpp"

#include <algorithm>
#include <cmath>

namespace geodem {

double SecantStep::next(double x, double y, double target) {
  xs_.push_back(x);
  ys_.push_back(y);
  // Least-squares slope of the newest points (up to kWindow): with two points the
  // secant, with more an average that noisy evaluations cannot tip over as easily.
  constexpr std::size_t kWindow = 4;
  const std::size_t first = xs_.size() > kWindow ? xs_.size() - kWindow : 0;
  const auto n = static_cast<double>(xs_.size() - first);
  double mx = 0.0, my = 0.0;
  for (std::size_t j = first; j < xs_.size(); ++j) mx += xs_[j] / n, my += ys_[j] / n;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t j = first; j < xs_.size(); ++j) {
    sxx += (xs_[j] - mx) * (xs_[j] - mx);
    sxy += (xs_[j] - mx) * (ys_[j] - my);
  }
  double slope = slope0_;
  if (sxx > 1e-24 * (1.0 + mx * mx)) {
    const double s = sxy / sxx;
    // Same sign as the expected relation and not flat: a usable slope.
    if (s * slope0_ > 0.0 && std::abs(s) > 0.05 * std::abs(slope0_)) slope = s;
  }
  const double step = std::clamp((target - y) / slope, -max_step_, max_step_);
  return std::clamp(x + step, lo_, hi_);
}

namespace {
// Defaults: degrees of peak friction per degree of contact friction, log E per log young,
// Poisson's ratio per log(kt/kn), log c per log bond strength, degrees of residual
// friction per unit of rolling friction. From the 2D pair_0.9 soils of the examples;
// only the first step uses them.
constexpr double kFrictionSlope = 0.6, kYoungSlope = 1.0, kKtKnSlope = -0.08, kBondSlope = 1.0,
                 kRollingSlope = 15.0;
}  // namespace

CalibrationSearch::CalibrationSearch(const CalibrationTargets& targets,
                                     const SearchTolerances& tolerances,
                                     const MicroParameters& start)
    : t_(targets),
      tol_(tolerances),
      p_(start),
      bonds_(targets.cohesion > 0.0 && start.bond_strength > 0.0),
      friction_(kFrictionSlope, 12.0, 0.5, 80.0),
      young_(kYoungSlope, std::log(4.0), -1e9, 1e9),
      ktkn_(kKtKnSlope, 1.0, std::log(0.02), std::log(1.0)),
      bond_(kBondSlope, std::log(3.0), -1e9, 1e9),
      rolling_(kRollingSlope, 0.3, 0.0, 2.0) {}

double CalibrationSearch::miss(const MacroValues& m) const {
  double worst = std::abs(m.phi_peak_deg - t_.phi_peak_deg) / tol_.phi_deg;
  worst = std::max(worst, std::abs(m.cohesion - t_.cohesion) / tol_.cohesion);
  if (std::isfinite(t_.young_modulus))
    worst = std::max(worst, std::abs(m.young_modulus / t_.young_modulus - 1.0) / tol_.young);
  if (std::isfinite(t_.poisson_ratio))
    worst = std::max(worst, std::abs(m.poisson_ratio - t_.poisson_ratio) / tol_.poisson);
  if (std::isfinite(t_.phi_residual_deg))
    worst = std::max(worst, std::abs(m.phi_residual_deg - t_.phi_residual_deg) / tol_.phi_deg);
  return worst;
}

bool CalibrationSearch::met(const MacroValues& m) const {
  return miss(m) <= 1.0;
}

bool CalibrationSearch::record(const MacroValues& m) {
  if (met(m)) return true;
  MicroParameters n = p_;
  n.friction_deg = friction_.next(p_.friction_deg, m.phi_peak_deg, t_.phi_peak_deg);
  if (std::isfinite(t_.young_modulus) && m.young_modulus > 0.0)
    n.young = std::exp(
        young_.next(std::log(p_.young), std::log(m.young_modulus), std::log(t_.young_modulus)));
  if (std::isfinite(t_.poisson_ratio))
    n.kt_over_kn = std::exp(ktkn_.next(std::log(p_.kt_over_kn), m.poisson_ratio, t_.poisson_ratio));
  if (bonds_) {
    // log c against log strength; a fit that gives no cohesion counts as a tenth of it.
    const double c = std::max(m.cohesion, 0.1 * t_.cohesion);
    n.bond_strength =
        std::exp(bond_.next(std::log(p_.bond_strength), std::log(c), std::log(t_.cohesion)));
  }
  if (std::isfinite(t_.phi_residual_deg))
    n.rolling_friction =
        rolling_.next(p_.rolling_friction, m.phi_residual_deg, t_.phi_residual_deg);
  p_ = n;
  return false;
}

}  // namespace geodem
