#include "lab/element_test_results.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "lab/soil_parameters.hpp"
#include "study/linear_fit.hpp"

namespace geodem {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// Slope of y against x by least squares (study/linear_fit) over the points [first, last];
// NaN where it is not defined (fewer than two points, or one x).
double slope(const std::vector<double>& x, const std::vector<double>& y, std::size_t first,
             std::size_t last) {
  if (last <= first || last >= x.size()) return std::nan("");
  const auto a = static_cast<std::ptrdiff_t>(first), b = static_cast<std::ptrdiff_t>(last) + 1;
  try {
    return fit_line({x.begin() + a, x.begin() + b}, {y.begin() + a, y.begin() + b}).slope;
  } catch (const std::invalid_argument&) {
    return std::nan("");
  }
}

// A number, or null where it is not defined (JSON has no NaN).
nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// Mean of v over the points whose x is in the last fifth of x's range.
double mean_of_last_fifth(const std::vector<double>& x, const std::vector<double>& v) {
  const double from = x.front() + 0.8 * (x.back() - x.front());
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] >= from) sum += v[i], ++n;
  return n > 0 ? sum / n : v.back();
}

}  // namespace

nlohmann::json stress_step_results(const StressSteps& s, LabKind kind, int dimension) {
  const bool oedometer = kind == LabKind::kOedometer;
  const std::size_t n = s.void_ratio.size();
  std::vector<double> stress(n), log_stress(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double p =
        (s.sigma_axial[i] + (dimension - 1) * s.sigma_lateral[i]) / static_cast<double>(dimension);
    stress[i] = oedometer ? s.sigma_axial[i] : p;
    log_stress[i] = std::log10(stress[i]);
  }
  nlohmann::json r;
  if (n == 0) return r;
  const auto top =
      static_cast<std::size_t>(std::max_element(stress.begin(), stress.end()) - stress.begin());
  const double cc = -slope(log_stress, s.void_ratio, 0, top);
  const double cs = -slope(log_stress, s.void_ratio, top, n - 1);
  r["stress_measure"] = oedometer ? "axial stress" : "mean stress";
  r["void_ratio_initial"] = s.void_ratio.front();
  r["void_ratio_at_largest_stress"] = s.void_ratio[top];
  r["void_ratio_end"] = s.void_ratio.back();
  r["compression_index"] = number_or_null(cc);
  r["swelling_index"] = number_or_null(cs);
  r["lambda"] = number_or_null(cc / std::numbers::ln10);
  r["kappa"] = number_or_null(cs / std::numbers::ln10);
  // The tangent modulus of each step: from point i - 1 to point i.
  const auto& strain = oedometer ? s.axial_strain : s.volumetric_strain;
  nlohmann::json moduli = nlohmann::json::array();
  for (std::size_t i = 1; i < n; ++i) {
    const double de = strain[i] - strain[i - 1];
    moduli.push_back(number_or_null(de != 0.0 ? (stress[i] - stress[i - 1]) / de : std::nan("")));
  }
  r[oedometer ? "constrained_modulus" : "bulk_modulus"] = moduli;
  nlohmann::json points = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i) {
    nlohmann::json p = {{"target", s.target[i]},
                        {"sigma_axial", s.sigma_axial[i]},
                        {"sigma_lateral", s.sigma_lateral[i]},
                        {"axial_strain", s.axial_strain[i]},
                        {"volumetric_strain", s.volumetric_strain[i]},
                        {"void_ratio", s.void_ratio[i]}};
    if (oedometer) p["K0"] = s.sigma_lateral[i] / s.sigma_axial[i];
    points.push_back(p);
  }
  r["points"] = points;
  if (oedometer) {
    // K0 of a normally consolidated soil: the slope of sigma_h against sigma_v on loading,
    // over the points at twice the starting stress and more, where the isotropic start no
    // longer weighs (all loading points if fewer than two are that far).
    std::size_t first = 0;
    while (first < top && s.sigma_axial[first] < 2.0 * s.sigma_axial[0]) ++first;
    if (top - first < 1) first = 0;
    r["K0_loading"] = number_or_null(slope(s.sigma_axial, s.sigma_lateral, first, top));
    r["K0_at_largest_stress"] = s.sigma_lateral[top] / s.sigma_axial[top];
    r["K0_end"] = s.sigma_lateral.back() / s.sigma_axial.back();
  }
  return r;
}

nlohmann::json simple_shear_results(const ShearCurve& c) {
  nlohmann::json r;
  const std::size_t n = c.shear_strain.size();
  if (n < 2) return r;
  std::vector<double> ratio(n);
  for (std::size_t i = 0; i < n; ++i) ratio[i] = c.shear_stress[i] / c.normal_stress[i];
  const auto ip = static_cast<std::size_t>(
      std::max_element(c.shear_stress.begin(), c.shear_stress.end()) - c.shear_stress.begin());
  const auto ir =
      static_cast<std::size_t>(std::max_element(ratio.begin(), ratio.end()) - ratio.begin());
  r["normal_stress_initial"] = c.normal_stress.front();
  r["tau_peak"] = c.shear_stress[ip];
  r["shear_strain_at_peak"] = c.shear_strain[ip];
  r["normal_stress_at_peak"] = c.normal_stress[ip];
  r["stress_ratio_peak"] = ratio[ir];
  r["phi_plane_peak_deg"] = std::atan(ratio[ir]) * kDeg;
  const double residual = mean_of_last_fifth(c.shear_strain, ratio);
  r["stress_ratio_residual"] = residual;
  r["phi_plane_residual_deg"] = std::atan(residual) * kDeg;
  r["phi_mobilised_peak_deg"] =
      *std::max_element(c.phi_mobilised_deg.begin(), c.phi_mobilised_deg.end());
  r["phi_mobilised_residual_deg"] = mean_of_last_fifth(c.shear_strain, c.phi_mobilised_deg);
  // Dilatancy at the peak stress ratio: tan(psi) = -d eps_n / d gamma, fitted over a tenth of
  // the strain range on each side.
  const double half = 0.1 * (c.shear_strain.back() - c.shear_strain.front());
  std::size_t a = ir, b = ir;
  while (a > 0 && c.shear_strain[a - 1] >= c.shear_strain[ir] - half) --a;
  while (b + 1 < n && c.shear_strain[b + 1] <= c.shear_strain[ir] + half) ++b;
  const double tan_psi = -slope(c.shear_strain, c.normal_strain, a, b);
  r["dilatancy_deg"] = number_or_null(std::atan(tan_psi) * kDeg);
  // Taylor's energy correction: the part of the peak stress ratio that lifts the normal load,
  // tan(psi), taken off: the friction of the shearing alone.
  r["phi_peak_dilatancy_corrected_deg"] = number_or_null(std::atan(ratio[ir] - tan_psi) * kDeg);
  // G50: secant to half the peak shear stress (interpolated).
  double g50 = std::nan("");
  for (std::size_t i = 1; i <= ip; ++i)
    if (c.shear_stress[i] >= 0.5 * c.shear_stress[ip]) {
      const double t = 0.5 * c.shear_stress[ip];
      const double f = (t - c.shear_stress[i - 1]) / (c.shear_stress[i] - c.shear_stress[i - 1]);
      const double g = c.shear_strain[i - 1] + f * (c.shear_strain[i] - c.shear_strain[i - 1]);
      if (g > 0.0) g50 = t / g;
      break;
    }
  r["shear_modulus_50"] = number_or_null(g50);
  r["tau_end"] = c.shear_stress.back();
  r["normal_stress_end"] = c.normal_stress.back();
  r["stress_ratio_end"] = ratio.back();
  r["normal_strain_end"] = c.normal_strain.back();
  r["void_ratio_initial"] = c.void_ratio.front();
  r["void_ratio_end"] = c.void_ratio.back();
  return r;
}

nlohmann::json direct_shear_results(const ShearCurve& c) {
  nlohmann::json r = simple_shear_results(c);
  if (r.is_null()) return r;
  const auto rename = [&](const char* from, const char* to) {
    r[to] = r[from];
    r.erase(from);
  };
  rename("shear_strain_at_peak", "displacement_at_peak");
  rename("shear_modulus_50", "shear_stiffness_50");
  rename("phi_plane_peak_deg", "phi_peak_deg");
  rename("phi_plane_residual_deg", "phi_residual_deg");
  rename("normal_strain_end", "plate_rise_end");
  r["plate_rise_end"] = -r["plate_rise_end"].get<double>();
  r.erase("phi_mobilised_peak_deg");
  r.erase("phi_mobilised_residual_deg");
  return r;
}

ShearEnvelope fit_shear_envelope(const std::vector<double>& sigma_n,
                                 const std::vector<double>& tau) {
  ShearEnvelope e;
  // One normal stress (or the same one repeated): the line through the origin.
  if (*std::min_element(sigma_n.begin(), sigma_n.end()) ==
      *std::max_element(sigma_n.begin(), sigma_n.end())) {
    e.phi_deg = std::atan(mean(tau) / sigma_n[0]) * kDeg;
    return e;
  }
  const LinearFit f = fit_line(sigma_n, tau);
  e.phi_deg = std::atan(f.slope) * kDeg;
  e.cohesion = f.intercept;
  return e;
}

nlohmann::json shear_envelopes(const nlohmann::json& tests) {
  std::vector<double> sn, tau, sn_res, tau_res;
  for (const auto& r : tests) {
    sn.push_back(r["normal_stress_at_peak"]), tau.push_back(r["tau_peak"]);
    const double s = r["normal_stress_initial"];
    sn_res.push_back(s), tau_res.push_back(s * r["stress_ratio_residual"].get<double>());
  }
  const ShearEnvelope peak = fit_shear_envelope(sn, tau), res = fit_shear_envelope(sn_res, tau_res);
  return {{"cohesion", peak.cohesion},
          {"phi_deg", peak.phi_deg},
          {"residual_cohesion", res.cohesion},
          {"residual_phi_deg", res.phi_deg}};
}

CycleResult CycleMeter::result() const {
  CycleResult r;
  const double dg = gamma_hi - gamma_lo, dt = tau_hi - tau_lo;
  r.shear_strain_amplitude = 0.5 * dg;
  r.shear_modulus = dg > 0.0 ? dt / dg : 0.0;
  const double stored = 0.5 * (0.5 * dt) * (0.5 * dg);
  r.damping_ratio = stored > 0.0 ? work / (4.0 * std::numbers::pi * stored) : 0.0;
  // q = 2 tau
  r.young_modulus = eps_hi != eps_lo ? 2.0 * dt / (eps_hi - eps_lo) : 0.0;
  return r;
}

nlohmann::json cyclic_results(const std::vector<double>& amplitudes, int cycles,
                              const std::vector<CycleResult>& loops, const char* amplitude_name) {
  nlohmann::json r, curve = nlohmann::json::array();
  const auto per = static_cast<std::size_t>(cycles);
  const std::size_t done = std::min(amplitudes.size(), loops.size() / per);
  if (done == 0) return r;
  const double g_max = loops[per - 1].shear_modulus;
  for (std::size_t a = 0; a < done; ++a) {
    const CycleResult& last = loops[(a + 1) * per - 1];
    nlohmann::json every = nlohmann::json::array();
    for (std::size_t k = a * per; k < (a + 1) * per; ++k)
      every.push_back(
          {{"shear_modulus", loops[k].shear_modulus}, {"damping_ratio", loops[k].damping_ratio}});
    curve.push_back({{amplitude_name, amplitudes[a]},
                     {"shear_strain_amplitude", last.shear_strain_amplitude},
                     {"shear_modulus", last.shear_modulus},
                     {"G_over_Gmax", g_max > 0.0 ? last.shear_modulus / g_max : 0.0},
                     {"damping_ratio", last.damping_ratio},
                     {"young_modulus", last.young_modulus},
                     {"loops", every}});
  }
  r["shear_modulus_max"] = g_max;
  r["amplitudes"] = curve;
  return r;
}

nlohmann::json lab_run_results(LabKind kind, const nlohmann::json& preparation,
                               const nlohmann::json& tests) {
  nlohmann::json results;
  results["preparation"] = preparation;
  results["tests"] = tests;
  if (tests.size() == 1)
    for (auto& [k, v] : tests[0].items()) results[k] = v;  // the contract's flat keys
  if (kind == LabKind::kSimpleShear || kind == LabKind::kDirectShear) {
    results["shear_envelope"] = shear_envelopes(tests);
  } else if (kind == LabKind::kTriaxial && tests.size() > 1) {
    std::vector<double> s1, s3;
    for (const auto& t : tests) s1.push_back(t["sigma1_peak"]), s3.push_back(t["sigma3_peak"]);
    const MohrCoulomb mc = fit_mohr_coulomb(s1, s3);
    results["mohr_coulomb"] = {{"cohesion", mc.cohesion}, {"phi_deg", mc.phi_deg}};
  }
  return results;
}

}  // namespace geodem
