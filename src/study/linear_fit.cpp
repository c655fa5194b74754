#include "study/linear_fit.hpp"

#include <cmath>
#include <stdexcept>

namespace geodem {

double mean(const std::vector<double>& v) {
  if (v.empty()) return 0.0;
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double standard_deviation(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

LinearFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size() || x.size() < 2)
    throw std::invalid_argument("a line fit needs two points or more");
  const double n = static_cast<double>(x.size());
  const double mx = mean(x), my = mean(y);
  // Centred sums: well conditioned when x is far from zero.
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (!(sxx > 0.0)) throw std::invalid_argument("a line fit needs two distinct x values");
  LinearFit f;
  f.points = x.size();
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double ss_res = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - f.at(x[i]);
    ss_res += r * r;
  }
  f.r2 = syy > 0.0 ? 1.0 - ss_res / syy : 1.0;
  if (x.size() > 2) {
    const double s2 = ss_res / (n - 2.0);  // residual variance
    f.slope_error = std::sqrt(s2 / sxx);
    f.intercept_error = std::sqrt(s2 * (1.0 / n + mx * mx / sxx));
  }
  return f;
}

}  // namespace geodem
