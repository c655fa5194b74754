#include "lab/interface_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "study/linear_fit.hpp"

namespace geodem {

namespace {
constexpr double kDeg = 180.0 / std::numbers::pi;

// Value of y at x by linear interpolation over the (increasing) abscissae xs.
double at(const std::vector<double>& xs, const std::vector<double>& y, double x) {
  if (x <= xs.front()) return y.front();
  if (x >= xs.back()) return y.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
  const double t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
  return y[k - 1] + t * (y[k] - y[k - 1]);
}
}  // namespace

InterfaceTest interface_test(const InterfaceCurve& c, double residual_from) {
  const std::size_t n = c.displacement.size();
  if (n < 3 || c.shear.size() != n || c.normal.size() != n || c.dilation.size() != n)
    throw std::invalid_argument("interface curve needs at least 3 consistent points");
  InterfaceTest t;
  double sn = 0.0;
  for (double s : c.normal) sn += s;
  t.normal_stress = sn / static_cast<double>(n);
  std::size_t ipeak = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (c.shear[i] > c.shear[ipeak]) ipeak = i;
  t.peak_shear = c.shear[ipeak];
  t.displacement_at_peak = c.displacement[ipeak];
  t.peak_ratio = c.normal[ipeak] > 0.0 ? c.shear[ipeak] / c.normal[ipeak] : 0.0;
  t.normal_at_peak = c.normal[ipeak];

  const double u_end = c.displacement.back();
  double rs = 0.0, rn = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (c.displacement[i] >= residual_from * u_end) rs += c.shear[i], rn += c.normal[i], ++count;
  t.residual_shear = rs / static_cast<double>(count);
  t.residual_ratio = rn > 0.0 ? rs / rn : 0.0;
  t.residual_normal = rn / static_cast<double>(count);

  // Secant stiffness: the first point where tau reaches half its peak (interpolated).
  const double half = 0.5 * t.peak_shear;
  for (std::size_t i = 1; i <= ipeak; ++i)
    if (c.shear[i] >= half) {
      const double f = (half - c.shear[i - 1]) / (c.shear[i] - c.shear[i - 1]);
      const double u = c.displacement[i - 1] + f * (c.displacement[i] - c.displacement[i - 1]);
      t.shear_stiffness = u > 0.0 ? half / u : 0.0;
      break;
    }

  t.dilation_max = *std::max_element(c.dilation.begin(), c.dilation.end());
  t.dilation_end = c.dilation.back();
  // Rise per slip over a window of a tenth of the travel centred on the peak.
  const double h = 0.05 * u_end;
  const double a = std::max(c.displacement.front(), t.displacement_at_peak - h);
  const double b = std::min(u_end, t.displacement_at_peak + h);
  if (b > a)
    t.dilation_angle_deg =
        std::atan((at(c.displacement, c.dilation, b) - at(c.displacement, c.dilation, a)) /
                  (b - a)) *
        kDeg;
  return t;
}

InterfaceEnvelope fit_interface_envelope(const std::vector<double>& normal,
                                         const std::vector<double>& shear) {
  InterfaceEnvelope e;
  if (normal.empty() || normal.size() != shear.size()) return e;
  const bool distinct =
      std::any_of(normal.begin(), normal.end(), [&](double s) { return s != normal.front(); });
  if (normal.size() < 2 || !distinct) {
    e.friction_deg = std::atan(shear.front() / normal.front()) * kDeg;
    return e;
  }
  const LinearFit f = fit_line(normal, shear);
  e.friction_deg = std::atan(f.slope) * kDeg;
  e.adhesion = f.intercept;
  e.r2 = f.r2;
  e.fitted = true;
  return e;
}

}  // namespace geodem
