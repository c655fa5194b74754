// Soil parameters read from a compression curve, on synthetic curves whose answers
// are known in closed form; the Mohr-Coulomb fit recovers c and phi exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lab/soil_parameters.hpp"

namespace geodem {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// q rises to qp at eps_p and softens: q = qp 2x/(1 + x^2), x = eps/eps_p; the
// volumetric strain is linear, eps_v = k eps_1.
CompressionCurve synthetic(int dim, double sigma3, double qp, double eps_p, double k,
                           int n = 4001) {
  CompressionCurve c;
  c.dimension = dim;
  for (int i = 0; i < n; ++i) {
    const double e = 0.15 * i / (n - 1), x = e / eps_p;
    c.axial_strain.push_back(e);
    c.volumetric_strain.push_back(k * e);
    c.sigma3.push_back(sigma3);
    c.sigma1.push_back(sigma3 + qp * 2 * x / (1 + x * x));
  }
  return c;
}

TEST(SoilParameters, SyntheticTriaxialCurve) {
  const double s3 = 1e5, qp = 2e5, ep = 0.03;
  const auto c = synthetic(3, s3, qp, ep, 0.4);
  const SoilParameters p = soil_parameters(c);
  EXPECT_NEAR(p.peak_q, qp, 1e-6 * qp);
  EXPECT_NEAR(p.axial_strain_at_peak, ep, 1e-4);
  EXPECT_NEAR(p.phi_peak_deg, std::asin(qp / (qp + 2 * s3)) * kDeg, 1e-6);
  // q = qp/2 at x = 2 - sqrt(3): E50 = (qp/2) / ((2 - sqrt 3) eps_p).
  const double e50 = 0.5 * qp / ((2 - std::sqrt(3.0)) * ep);
  EXPECT_NEAR(p.young_modulus, e50, 1e-3 * e50);
  // eps_v = 0.4 eps_1: nu = (1 - 0.4)/2 = 0.3; sin(psi) = -0.4/(2 - 0.4).
  EXPECT_NEAR(p.poisson_ratio, 0.3, 1e-9);
  EXPECT_NEAR(p.dilatancy_deg, std::asin(-0.25) * kDeg, 1e-6);
  // Residual: the mean mobilised angle over the last fifth (12 % to 15 % strain).
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < c.axial_strain.size(); ++i)
    if (c.axial_strain[i] >= 0.12 - 1e-12) {
      sum += std::asin((c.sigma1[i] - s3) / (c.sigma1[i] + s3)) * kDeg;
      ++n;
    }
  EXPECT_NEAR(p.phi_residual_deg, sum / n, 1e-9);
  EXPECT_LT(p.phi_residual_deg, p.phi_peak_deg);
}

TEST(SoilParameters, BiaxialPoissonAndDilatancy) {
  const auto c = synthetic(2, 5e4, 6e4, 0.02, -0.5);  // dilating: eps_v = -0.5 eps_1
  const SoilParameters p = soil_parameters(c);
  EXPECT_NEAR(p.poisson_ratio, 1.5, 1e-9);  // plane strain, in-plane: 1 - dv/d1
  EXPECT_NEAR(p.dilatancy_deg, std::asin(0.5 / 2.5) * kDeg, 1e-6);
}

TEST(MohrCoulomb, RecoversCohesionAndFrictionExactly) {
  for (double phi : {20.0, 35.0, 45.0})
    for (double c : {0.0, 1e4, 3.7e4}) {
      const double t = std::tan((45.0 + phi / 2) / kDeg);
      std::vector<double> s1, s3 = {2.5e4, 5e4, 1e5, 2e5};
      for (double v : s3) s1.push_back(v * t * t + 2 * c * t);
      const MohrCoulomb mc = fit_mohr_coulomb(s1, s3);
      EXPECT_NEAR(mc.phi_deg, phi, 1e-9);
      EXPECT_NEAR(mc.cohesion, c, 1e-6);
    }
}

TEST(MohrCoulomb, NeedsTwoTests) {
  EXPECT_THROW(fit_mohr_coulomb({3e5}, {1e5}), std::invalid_argument);
}

}  // namespace
}  // namespace geodem
