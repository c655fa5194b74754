// The element tests' results against closed forms: the damping ratio and secant modulus of
// a linear viscoelastic loop (D = tan(delta) / 2), compression and swelling indices and K0 of
// stepped loading on exact logarithmic and linear laws, the simple-shear friction, dilatancy
// and G50 of a piecewise-linear curve, and the shear envelope of points on a line.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lab/element_test_results.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

constexpr double kPi = std::numbers::pi;

// tau = tau_a cos(theta + delta), gamma = gamma_a cos(theta): the loop's area is
// pi tau_a gamma_a sin(delta); its turning points are at theta = 0 and pi, where
// tau = +-tau_a cos(delta): G = tau_a cos(delta) / gamma_a, and D = tan(delta) / 2.
TEST(ElementTestResults, CycleMeterGivesTheViscoelasticLoopsDamping) {
  for (double delta : {0.0, 0.05, 0.3}) {
    const double tau_a = 2e4, gamma_a = 1e-3;
    CycleMeter m;
    const int n = 20000;
    for (int i = 0; i <= n; ++i) {
      const double th = 2.0 * kPi * i / n;
      const double tau = tau_a * std::cos(th + delta), gamma = gamma_a * std::cos(th);
      if (i == 0) m.start(tau, gamma), m.turn_high(tau, gamma, gamma);
      m.add(tau, gamma);
      if (i == n / 2) m.turn_low(tau, gamma, gamma);
    }
    const CycleResult r = m.result();
    EXPECT_NEAR(r.damping_ratio, 0.5 * std::tan(delta), 1e-7) << delta;
    EXPECT_NEAR(r.shear_modulus / (tau_a * std::cos(delta) / gamma_a), 1.0, 1e-12);
    EXPECT_NEAR(r.shear_strain_amplitude, gamma_a, 1e-15);
    report("loop damping error, delta " + std::to_string(delta),
           std::abs(r.damping_ratio - 0.5 * std::tan(delta)));
  }
}

TEST(ElementTestResults, CyclicResultsTakeEachAmplitudesLastLoop) {
  std::vector<CycleResult> loops(4);
  loops[0].shear_modulus = 9.0, loops[1].shear_modulus = 10.0;  // amplitude 1: Gmax = 10
  loops[2].shear_modulus = 7.0, loops[3].shear_modulus = 6.0, loops[3].damping_ratio = 0.1;
  const auto r = cyclic_results({1e-5, 1e-3}, 2, loops);
  EXPECT_DOUBLE_EQ(r["shear_modulus_max"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(r["amplitudes"][1]["G_over_Gmax"].get<double>(), 0.6);
  EXPECT_DOUBLE_EQ(r["amplitudes"][1]["damping_ratio"].get<double>(), 0.1);
  EXPECT_EQ(r["amplitudes"][1]["loops"].size(), 2u);
}

// e = e0 - Cc log10(s) on loading to the largest stress, e = e_top - Cs log10(s / s_top) on
// unloading; sigma_h = 0.45 sigma_v + 2e4 on loading (K0 slope 0.45).
TEST(ElementTestResults, StressStepsGiveTheIndicesAndK0OfExactLaws) {
  const double cc = 0.12, cs = 0.02, e0 = 0.9;
  StressSteps s;
  const std::vector<double> sv = {5e4, 1e5, 2e5, 4e5, 8e5, 2e5, 5e4};
  double e_top = 0.0;
  for (std::size_t i = 0; i < sv.size(); ++i) {
    const bool loading = i <= 4;
    const double e = loading ? e0 - cc * std::log10(sv[i]) : e_top - cs * std::log10(sv[i] / 8e5);
    if (i == 4) e_top = e;
    s.target.push_back(sv[i]);
    s.sigma_axial.push_back(sv[i]);
    s.sigma_lateral.push_back(loading ? 0.45 * sv[i] + 2e4 : 0.8 * sv[i]);
    s.axial_strain.push_back((e0 - cc * std::log10(5e4) - e) / 1.5);
    s.volumetric_strain.push_back(s.axial_strain.back());
    s.void_ratio.push_back(e);
  }
  const auto r = stress_step_results(s, LabKind::kOedometer, 3);
  EXPECT_NEAR(r["compression_index"].get<double>(), cc, 1e-12);
  EXPECT_NEAR(r["swelling_index"].get<double>(), cs, 1e-12);
  EXPECT_NEAR(r["lambda"].get<double>(), cc / std::log(10.0), 1e-12);
  // Loading points at twice the start and more: 1e5 .. 8e5, on the line of slope 0.45.
  EXPECT_NEAR(r["K0_loading"].get<double>(), 0.45, 1e-12);
  EXPECT_NEAR(r["K0_end"].get<double>(), 0.8, 1e-12);
  // Constrained modulus of the first step: d sigma / d eps_a.
  const double de = s.axial_strain[1] - s.axial_strain[0];
  EXPECT_NEAR(r["constrained_modulus"][0].get<double>(), 5e4 / de, 1e-6 * 5e4 / de);
  // Isotropic: the mean stress of (s_a + 2 s_l) / 3 is the abscissa.
  const auto iso = stress_step_results(s, LabKind::kIsotropic, 3);
  EXPECT_TRUE(iso.contains("bulk_modulus"));
  EXPECT_FALSE(iso.contains("K0_loading"));
}

// tau rises linearly to 0.5 sigma_n at gamma = 0.1, then falls to 0.4 sigma_n; eps_n =
// -0.2 gamma throughout (dilatancy atan(0.2)); the principal friction follows the ratio.
TEST(ElementTestResults, SimpleShearCurveGivesPeakResidualDilatancyAndG50) {
  ShearCurve c;
  const double sn = 1e5;
  for (int i = 0; i <= 300; ++i) {
    const double g = 0.001 * i;
    const double ratio = g <= 0.1 ? 5.0 * g : std::max(0.4, 0.5 - (g - 0.1));
    c.shear_strain.push_back(g);
    c.shear_stress.push_back(ratio * sn);
    c.normal_stress.push_back(sn);
    c.normal_strain.push_back(-0.2 * g);
    c.phi_mobilised_deg.push_back(std::atan(ratio) * 180.0 / kPi);
    c.void_ratio.push_back(0.2 + 0.2 * g);
  }
  const auto r = simple_shear_results(c);
  EXPECT_NEAR(r["stress_ratio_peak"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(r["phi_plane_peak_deg"].get<double>(), std::atan(0.5) * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(r["phi_plane_residual_deg"].get<double>(), std::atan(0.4) * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(r["shear_strain_at_peak"].get<double>(), 0.1, 1e-12);
  EXPECT_NEAR(r["dilatancy_deg"].get<double>(), std::atan(0.2) * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(r["phi_peak_dilatancy_corrected_deg"].get<double>(),
              std::atan(0.5 - 0.2) * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(r["shear_modulus_50"].get<double>(), 5.0 * sn, 1e-6 * sn);  // tau / gamma
}

TEST(ElementTestResults, ShearEnvelopeOfPointsOnALine) {
  const double c = 5e3, tan_phi = 0.6;
  const auto e = fit_shear_envelope({5e4, 1e5, 2e5},
                                    {c + 5e4 * tan_phi, c + 1e5 * tan_phi, c + 2e5 * tan_phi});
  EXPECT_NEAR(e.cohesion, c, 1e-8);
  EXPECT_NEAR(e.phi_deg, std::atan(tan_phi) * 180.0 / kPi, 1e-12);
  const auto one = fit_shear_envelope({1e5}, {5e4});
  EXPECT_NEAR(one.phi_deg, std::atan(0.5) * 180.0 / kPi, 1e-12);
  EXPECT_EQ(one.cohesion, 0.0);
  const auto repeated = fit_shear_envelope({1e5, 1e5}, {4e4, 6e4});  // through the origin
  EXPECT_NEAR(repeated.phi_deg, std::atan(0.5) * 180.0 / kPi, 1e-12);
  EXPECT_EQ(repeated.cohesion, 0.0);
}

}  // namespace
}  // namespace geodem::test
