// What the element tests report (docs/lab_tests.md): compression and swelling indices,
// constrained and bulk moduli and K0 from the points at rest of stepped loading; friction
// and dilatancy from a simple-shear curve; secant shear modulus and damping ratio from the
// loops of a cyclic test. Stresses compression positive (Pa).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "lab/element_test_settings.hpp"

namespace geodem {

// The points at rest of an isotropic or oedometer test: the consolidated start, then the
// end of each stress step. Strains from the start, compression positive.
struct StressSteps {
  std::vector<double> target, sigma_axial, sigma_lateral, axial_strain, volumetric_strain,
      void_ratio;
};

// Isotropic: index against log10 of the mean stress; oedometer: of the axial stress.
// compression_index (loading branch, up to the largest stress) and swelling_index (from
// there on), their natural-log slopes lambda and kappa, the tangent modulus of each step
// (bulk K = dp / d eps_v, or constrained M = d sigma_v / d eps_a), and for the oedometer K0
// = sigma_h / sigma_v at each point and the slope d sigma_h / d sigma_v on loading.
nlohmann::json stress_step_results(const StressSteps& s, LabKind kind, int dimension);

// A simple-shear curve: engineering shear strain (the cell's tilt), shear and normal
// stress on the shear plane, normal strain, the friction mobilised by the principal
// stresses (sin phi = (s1 - s3) / (s1 + s3)), void ratio.
struct ShearCurve {
  std::vector<double> shear_strain, shear_stress, normal_stress, normal_strain, phi_mobilised_deg,
      void_ratio;
};
nlohmann::json simple_shear_results(const ShearCurve& c);
// A direct shear curve in the same form: the frame's displacement (m) for the shear strain,
// minus the plate's rise for the normal strain, atan(tau / sigma_n) for the friction.
// Results as the simple shear's, with the displacement's names (displacement_at_peak,
// shear_stiffness_50 in Pa/m, phi_peak_deg and phi_residual_deg of tau / sigma_n).
nlohmann::json direct_shear_results(const ShearCurve& c);

// tau = c + sigma_n tan(phi) by least squares over the tests' peaks.
struct ShearEnvelope {
  double cohesion = 0.0, phi_deg = 0.0;
};
ShearEnvelope fit_shear_envelope(const std::vector<double>& sigma_n,
                                 const std::vector<double>& tau);

// The peak envelope (tau_peak against the normal stress at the peak) and the residual one
// (the residual stress ratio times the test's normal stress) of shear tests' results:
// {"cohesion", "phi_deg", "residual_cohesion", "residual_phi_deg"}.
nlohmann::json shear_envelopes(const nlohmann::json& tests);

// The results of a triaxial-kind run: its preparation, its tests (and, for one test, the
// contract's flat keys), the shear envelope of shear tests or the Mohr-Coulomb fit of several
// triaxial tests' peaks (sigma1_peak, sigma3_peak).
nlohmann::json lab_run_results(LabKind kind, const nlohmann::json& preparation,
                               const nlohmann::json& tests);

// One loop of a cyclic test in the shear stress tau = (sigma_a - sigma_r) / 2 and shear
// strain gamma = eps_a - eps_r (the largest shear stress and strain of an axisymmetric, or
// plane, state): the secant modulus G = (tau_hi - tau_lo) / (gamma_hi - gamma_lo) between
// its turning points, and the damping ratio D = W / (4 pi W_s), W the energy dissipated
// in the loop (its area) and W_s = tau_a gamma_a / 2 the strain energy at the amplitudes.
struct CycleResult {
  double shear_strain_amplitude = 0.0, shear_modulus = 0.0, damping_ratio = 0.0;
  double young_modulus = 0.0;  // secant (q_hi - q_lo) / (eps_a,hi - eps_a,lo)
  template <class Archive>
  void visit(Archive& a) {
    a(shear_strain_amplitude), a(shear_modulus), a(damping_ratio), a(young_modulus);
  }
};

// Integrates a loop step by step (trapezoids) from one compression turning point to the
// next one, and records its turning points.
struct CycleMeter {
  double work = 0.0, tau = 0.0, gamma = 0.0;  // work so far; the last point
  double tau_hi = 0.0, gamma_hi = 0.0, eps_hi = 0.0, tau_lo = 0.0, gamma_lo = 0.0, eps_lo = 0.0;
  std::uint8_t started = 0;

  void start(double t, double g) { work = 0.0, tau = t, gamma = g, started = 1; }
  void add(double t, double g) {
    if (started) work += 0.5 * (t + tau) * (g - gamma);
    tau = t, gamma = g;
  }
  void turn_high(double t, double g, double eps) { tau_hi = t, gamma_hi = g, eps_hi = eps; }
  void turn_low(double t, double g, double eps) { tau_lo = t, gamma_lo = g, eps_lo = eps; }
  CycleResult result() const;
  template <class Archive>
  void visit(Archive& a) {
    a(work), a(tau), a(gamma), a(tau_hi), a(gamma_hi), a(eps_hi), a(tau_lo), a(gamma_lo);
    a(eps_lo), a(started);
  }
};

// The cyclic test's results from its loops (`cycles` per amplitude, in order): each
// amplitude's last loop with G / Gmax (Gmax: the modulus of the smallest amplitude), and the
// modulus and damping of every loop.
// `amplitude_name` names the amplitudes given (axial_strain_amplitude, q_amplitude).
nlohmann::json cyclic_results(const std::vector<double>& amplitudes, int cycles,
                              const std::vector<CycleResult>& loops,
                              const char* amplitude_name = "axial_strain_amplitude");

}  // namespace geodem
