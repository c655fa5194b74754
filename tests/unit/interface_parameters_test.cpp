// The interface shear analysis (lab/interface_parameters.hpp) on synthetic curves with
// known answers: peak, residual over the last fifth, secant stiffness to half the peak,
// dilation angle around the peak, and the Mohr-Coulomb envelope of several tests.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lab/interface_parameters.hpp"

namespace geodem {
namespace {

// tau rises linearly (stiffness k) to a peak at u_p, falls linearly to a residual at
// 2 u_p and stays there; the plate rises at a constant rate (tan psi) past u_p / 2.
InterfaceCurve synthetic(double k, double u_p, double peak, double residual, double sigma,
                         double tan_psi) {
  InterfaceCurve c;
  for (int i = 1; i <= 400; ++i) {
    const double u = 0.1 * u_p * i / 10.0;  // up to 4 u_p
    double tau = 0.0;
    if (u <= peak / k) {
      tau = k * u;
    } else if (u <= u_p) {
      tau = peak;
    } else if (u <= 2.0 * u_p) {
      tau = peak + (residual - peak) * (u - u_p) / u_p;
    } else {
      tau = residual;
    }
    c.displacement.push_back(u);
    c.shear.push_back(tau);
    c.normal.push_back(sigma);
    c.dilation.push_back(u > 0.5 * u_p ? tan_psi * (u - 0.5 * u_p) : 0.0);
  }
  return c;
}

TEST(InterfaceParameters, PeakResidualStiffnessAndDilation) {
  const double k = 2e6, u_p = 0.01, peak = 8000.0, residual = 6000.0, sigma = 1e4;
  const InterfaceCurve c = synthetic(k, u_p, peak, residual, sigma, 0.1);
  const InterfaceTest t = interface_test(c);
  EXPECT_DOUBLE_EQ(t.peak_shear, peak);
  EXPECT_NEAR(t.displacement_at_peak, peak / k, 1e-12);  // the first point at the peak
  EXPECT_DOUBLE_EQ(t.peak_ratio, 0.8);
  EXPECT_NEAR(t.residual_shear, residual, 1e-9);  // past 0.8 x 4 u_p, all residual
  EXPECT_NEAR(t.residual_ratio, 0.6, 1e-12);
  EXPECT_NEAR(t.shear_stiffness, k, 1e-6 * k);
  EXPECT_NEAR(t.normal_stress, sigma, 1e-9);
  EXPECT_NEAR(t.dilation_end, 0.1 * (4.0 * u_p - 0.5 * u_p), 1e-12);
  EXPECT_NEAR(t.dilation_max, t.dilation_end, 1e-15);
  // Window of +-2 mm (5 % of the 40 mm travel) around the peak at 4 mm: the plate rises
  // from 5 mm on, 0.1 mm by 6 mm, so 0.1 mm over the window's 4 mm; a later peak sees the
  // full slope.
  EXPECT_NEAR(t.dilation_angle_deg, std::atan(0.1e-3 / 4e-3) * 180.0 / std::numbers::pi, 1e-9);
  InterfaceCurve late = c;
  for (std::size_t i = 0; i < late.shear.size(); ++i)
    late.shear[i] = late.displacement[i] <= 0.02 ? late.displacement[i] : 0.01;
  EXPECT_NEAR(interface_test(late).dilation_angle_deg, std::atan(0.1) * 180.0 / std::numbers::pi,
              1e-9);
}

TEST(InterfaceParameters, EnvelopeOfSeveralTests) {
  const double a = 1500.0, tan_delta = std::tan(30.0 * std::numbers::pi / 180.0);
  const std::vector<double> sn = {1e4, 2e4, 4e4};
  std::vector<double> tau;
  for (double s : sn) tau.push_back(a + s * tan_delta);
  const InterfaceEnvelope e = fit_interface_envelope(sn, tau);
  EXPECT_TRUE(e.fitted);
  EXPECT_NEAR(e.friction_deg, 30.0, 1e-9);
  EXPECT_NEAR(e.adhesion, a, 1e-6);
  EXPECT_NEAR(e.r2, 1.0, 1e-12);
  // One test: the line through the origin.
  const InterfaceEnvelope one = fit_interface_envelope({2e4}, {2e4 * tan_delta});
  EXPECT_FALSE(one.fitted);
  EXPECT_NEAR(one.friction_deg, 30.0, 1e-9);
  EXPECT_DOUBLE_EQ(one.adhesion, 0.0);
}

}  // namespace
}  // namespace geodem
