// Least-squares straight line y = intercept + slope x, with the standard errors of both
// and the coefficient of determination. The studies fit peak strength against sample
// size (d0/L) and against damping x strain rate; the fits are tested on synthetic data
// with known slopes and intercepts.
#pragma once

#include <vector>

namespace geodem {

struct LinearFit {
  double intercept = 0.0, slope = 0.0;
  double intercept_error = 0.0, slope_error = 0.0;  // standard errors (0 with two points)
  double r2 = 0.0;                                  // 1 for a perfect line
  std::size_t points = 0;
  double at(double x) const { return intercept + slope * x; }
};

// Needs two points or more with distinct x (else throws std::invalid_argument).
LinearFit fit_line(const std::vector<double>& x, const std::vector<double>& y);

double mean(const std::vector<double>& v);
// Sample standard deviation (n - 1); 0 for fewer than two values.
double standard_deviation(const std::vector<double>& v);

}  // namespace geodem
