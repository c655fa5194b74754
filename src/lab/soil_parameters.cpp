#include "lab/soil_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace geodem {

namespace {
constexpr double kDeg = 180.0 / std::numbers::pi;

// Slope of y against x by least squares over [a, b).
double slope(const std::vector<double>& x, const std::vector<double>& y, std::size_t a,
             std::size_t b) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(b - a);
  for (std::size_t i = a; i < b; ++i)
    sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  const double den = n * sxx - sx * sx;
  return den != 0.0 ? (n * sxy - sx * sy) / den : 0.0;
}
}  // namespace

double mobilised_friction_deg(double sigma1, double sigma3) {
  const double s = sigma1 + sigma3;
  if (s <= 0.0) return 0.0;
  return std::asin(std::clamp((sigma1 - sigma3) / s, -1.0, 1.0)) * kDeg;
}

SoilParameters soil_parameters(const CompressionCurve& c) {
  const std::size_t n = c.axial_strain.size();
  if (n < 3 || c.sigma1.size() != n || c.sigma3.size() != n || c.volumetric_strain.size() != n)
    throw std::invalid_argument("compression curve needs at least 3 consistent points");
  SoilParameters out;
  std::size_t ipeak = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (c.sigma1[i] - c.sigma3[i] > c.sigma1[ipeak] - c.sigma3[ipeak]) ipeak = i;
  out.peak_q = c.sigma1[ipeak] - c.sigma3[ipeak];
  out.axial_strain_at_peak = c.axial_strain[ipeak];
  out.phi_peak_deg = mobilised_friction_deg(c.sigma1[ipeak], c.sigma3[ipeak]);

  // Residual: mean mobilised angle over the last fifth of the strain range.
  const double e_end = c.axial_strain.back(), e0 = c.axial_strain.front();
  const double from = e_end - 0.2 * (e_end - e0);
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (c.axial_strain[i] >= from) sum += mobilised_friction_deg(c.sigma1[i], c.sigma3[i]), ++count;
  out.phi_residual_deg = count ? sum / count : out.phi_peak_deg;

  // E50: secant modulus from the start to half the peak deviator (q measured from its start).
  const double q0 = c.sigma1[0] - c.sigma3[0];
  const double half = q0 + 0.5 * (out.peak_q - q0);
  std::size_t ihalf = 1;
  while (ihalf < ipeak && c.sigma1[ihalf] - c.sigma3[ihalf] < half) ++ihalf;
  const double de = c.axial_strain[ihalf] - e0;
  if (de > 0.0) {
    // Interpolate the strain where q reaches half the peak.
    const double qa = c.sigma1[ihalf - 1] - c.sigma3[ihalf - 1],
                 qb = c.sigma1[ihalf] - c.sigma3[ihalf];
    const double t = qb > qa ? std::clamp((half - qa) / (qb - qa), 0.0, 1.0) : 1.0;
    const double e_half =
        c.axial_strain[ihalf - 1] + t * (c.axial_strain[ihalf] - c.axial_strain[ihalf - 1]) - e0;
    if (e_half > 0.0) out.young_modulus = (half - q0) / e_half;
  }
  // Poisson's ratio from the volumetric against axial slope over the same range:
  // triaxial: eps_v = eps_1 + 2 eps_3 -> nu = (1 - dv/d1)/2; biaxial (plane strain,
  // in-plane): eps_v = eps_1 + eps_3 -> nu_2D = 1 - dv/d1.
  const std::size_t iend = std::max<std::size_t>(ihalf + 1, 3);
  const double dv = slope(c.axial_strain, c.volumetric_strain, 0, std::min(iend, n));
  out.poisson_ratio = c.dimension == 3 ? 0.5 * (1.0 - dv) : 1.0 - dv;

  // Dilatancy around the peak: slope of eps_v against eps_1 over a window of 10 % of
  // the points centred on the peak (at least 3).
  const std::size_t w = std::max<std::size_t>(1, n / 20);
  const std::size_t a = ipeak > w ? ipeak - w : 0, b = std::min(n, ipeak + w + 1);
  const double dvp =
      slope(c.axial_strain, c.volumetric_strain, a, std::max(b, a + 3 <= n ? a + 3 : n));
  out.dilatancy_deg = std::asin(std::clamp(-dvp / (2.0 - dvp), -1.0, 1.0)) * kDeg;
  return out;
}

MohrCoulomb fit_mohr_coulomb(const std::vector<double>& s1, const std::vector<double>& s3) {
  if (s1.size() < 2 || s1.size() != s3.size())
    throw std::invalid_argument("a Mohr-Coulomb fit needs two tests or more");
  std::vector<double> p(s1.size()), q(s1.size());
  for (std::size_t i = 0; i < s1.size(); ++i)
    p[i] = 0.5 * (s1[i] + s3[i]), q[i] = 0.5 * (s1[i] - s3[i]);
  const double sin_phi = slope(p, q, 0, p.size());
  double mp = 0, mq = 0;
  for (std::size_t i = 0; i < p.size(); ++i) mp += p[i], mq += q[i];
  mp /= static_cast<double>(p.size()), mq /= static_cast<double>(p.size());
  const double intercept = mq - sin_phi * mp;  // c cos(phi)
  MohrCoulomb mc;
  mc.phi_deg = std::asin(std::clamp(sin_phi, -1.0, 1.0)) * kDeg;
  const double cos_phi = std::sqrt(std::max(0.0, 1.0 - sin_phi * sin_phi));
  mc.cohesion = cos_phi > 0.0 ? intercept / cos_phi : 0.0;
  return mc;
}

}  // namespace geodem
