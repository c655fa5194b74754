// The state of one test of the triaxial kind from its consolidation on, what the test
// reports from it, and the kind's CSV columns (lab/run_triaxial.cpp runs the test).
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "contacts/bonds.hpp"
#include "lab/soil_parameters.hpp"
#include "lab/triaxial_settings.hpp"
#include "measure/measurements.hpp"
#include "walls/lab_box.hpp"
#include "world/world.hpp"

namespace geodem {

// Diameter of the disc (2D) or sphere (3D) of volume v: the grain size d0 of a sample.
template <int D>
double equivalent_diameter(double v) {
  return D == 2 ? 2.0 * std::sqrt(v / std::numbers::pi) : std::cbrt(6.0 * v / std::numbers::pi);
}

// The state of one compression test from its consolidation on.
template <int D>
struct Shear {
  typename Dim<D>::Vec ref = Dim<D>::Vec::Zero();  // box size at the start of loading
  std::string warning;
  std::uint64_t bonds_made = 0, broken0 = 0;
  double porosity0 = 0.0, height0 = 0.0, d0 = 0.0;
  double eps = 0.0, next_record = 0.0;
  std::vector<double> vtk_left;  // strains of the VTK frames to come, largest first
  CompressionCurve curve;
  // The last recorded effective mean stress p' and deviator q, and the excess pore pressure
  // of an undrained test (its largest and last values).
  double p_end = 0.0, q_end = 0.0, u_max = 0.0, u_end = 0.0;

  template <class Archive>
  void visit(Archive& a) {
    a(ref), a(warning), a(bonds_made), a(broken0), a(porosity0), a(height0), a(d0), a(eps);
    a(next_record), a(vtk_left), a(curve.dimension), a(curve.axial_strain);
    a(curve.volumetric_strain), a(curve.sigma1), a(curve.sigma3);
    a(p_end), a(q_end), a(u_max), a(u_end);
  }

  // The excess pore pressure of an undrained test at this point: the total mean stress of a
  // test whose cell pressure stays sigma3 (p0 + q/3 in 3D, p0 + q/2 in 2D) minus the
  // effective one the grains carry, p'.
  static double excess_pore_pressure(double sigma3, double p, double q) {
    return sigma3 + q / (D == 3 ? 3.0 : 2.0) - p;
  }
};

inline std::vector<std::string> triaxial_prep_columns() {
  return {"phase",        "step",       "time",         "mean_stress", "porosity",
          "friction_deg", "unbalanced", "coordination", "radius_0"};
}

template <int D>
std::vector<std::string> triaxial_history_columns(bool bonds, bool undrained = false) {
  std::vector<std::string> cols = {"test",  "step", "time", "axial_strain", "volumetric_strain",
                                   "sigma1"};
  if (D == 3) cols.push_back("sigma2");
  for (const char* c : {"sigma3", "p", "q", "porosity", "coordination", "unbalanced"})
    cols.push_back(c);
  if (bonds) cols.insert(cols.end(), {"bonds", "broken_bonds"});
  if (undrained) cols.push_back("excess_pore_pressure");
  return cols;
}

// A finished test's results (summary.json, per test): the soil parameters of its curve,
// the peak's principal stresses (`sigma1_peak`, `sigma3_peak`), the size and rate
// measures of the studies, bonds and grain counts of the world `w` at its end.
template <int D>
nlohmann::json test_results(const Shear<D>& h, const TriaxialSettings& s, double sigma3,
                            const World<D>& w, bool bonds) {
  const SoilParameters sp = soil_parameters(h.curve);
  nlohmann::json r;
  r["confining_stress"] = sigma3;
  r["porosity_initial"] = h.porosity0;
  r["peak_q"] = sp.peak_q;
  r["axial_strain_at_peak"] = sp.axial_strain_at_peak;
  r["phi_peak_deg"] = sp.phi_peak_deg;
  r["phi_residual_deg"] = sp.phi_residual_deg;
  r["young_modulus"] = sp.young_modulus;
  r["poisson_ratio"] = sp.poisson_ratio;
  r["dilatancy_deg"] = sp.dilatancy_deg;
  // Peak principal stresses, for envelopes pooled over several runs (studies).
  const auto& c = h.curve;
  std::size_t ip = 0;
  for (std::size_t i = 0; i < c.sigma1.size(); ++i)
    if (c.sigma1[i] - c.sigma3[i] > c.sigma1[ip] - c.sigma3[ip]) ip = i;
  r["sigma1_peak"] = c.sigma1[ip];
  r["sigma3_peak"] = c.sigma3[ip];
  // Size and rate measures of the representativeness and rate studies.
  r["grain_size_d0"] = h.d0;
  r["sample_height"] = h.height0;
  r["d0_over_L"] = h.d0 / h.height0;
  r["inertial_number"] = s.strain_rate * h.d0 * std::sqrt(s.grain.density / sigma3);
  r["steps"] = w.step;
  // The end of the test, for critical-state lines pooled over drained and undrained tests.
  r["p_end"] = h.p_end;
  r["q_end"] = h.q_end;
  r["stress_ratio_end"] = h.p_end > 0.0 ? h.q_end / h.p_end : 0.0;
  r["drainage"] = s.undrained ? "undrained" : "drained";
  if (s.undrained) {
    r["excess_pore_pressure_max"] = h.u_max;
    r["excess_pore_pressure_end"] = h.u_end;
  }
  if (bonds) {
    r["bonds_at_start"] = s.bonds_create == "before_shear"
                              ? h.bonds_made
                              : intact_bonds(w) + (broken_bond_count(w) - h.broken0);
    r["bonds_broken"] = broken_bond_count(w) - h.broken0;
  }
  r["grains"] = body_count(w);
  if (!h.warning.empty()) r["warning"] = h.warning;
  return r;
}

// One row of the compression's history.csv (triaxial_history_columns) from the box and the
// sample now; the test's curve and end values take the point too.
template <int D>
std::vector<double> triaxial_history_row(Shear<D>& h, const LabBox<D>& box, const World<D>& w,
                                         const TriaxialSettings& s, std::uint64_t test,
                                         double sigma3, bool bonds) {
  constexpr int kAxial = D - 1;
  const double lat[2] = {box.stress(w, 0), D == 3 ? box.stress(w, 1) : 0.0};
  const double s1 = box.stress(w, kAxial);
  const double s2 = D == 3 ? std::max(lat[0], lat[1]) : lat[0];
  const double s3 = D == 3 ? std::min(lat[0], lat[1]) : lat[0];
  const double ev = box.volumetric_strain(w, h.ref);
  const double p = D == 3 ? (s1 + s2 + s3) / 3.0 : 0.5 * (s1 + s3);
  const double porosity = 1.0 - solid_volume(w) / box.volume(w);
  std::vector<double> row = {
      static_cast<double>(test), static_cast<double>(w.step), w.time, h.eps, ev, s1};
  if (D == 3) row.push_back(s2);
  for (double v : {s3, p, s1 - s3, porosity, coordination_number(w), unbalanced_force_ratio(w)})
    row.push_back(v);
  if (bonds) {
    row.push_back(static_cast<double>(intact_bonds(w)));
    row.push_back(static_cast<double>(broken_bond_count(w) - h.broken0));
  }
  h.p_end = p, h.q_end = s1 - s3;
  if (s.undrained) {
    h.u_end = Shear<D>::excess_pore_pressure(sigma3, p, s1 - s3);
    h.u_max = std::max(h.u_max, h.u_end);
    row.push_back(h.u_end);
  }
  h.curve.axial_strain.push_back(h.eps);
  h.curve.volumetric_strain.push_back(ev);
  h.curve.sigma1.push_back(s1);
  h.curve.sigma3.push_back(s3);
  return row;
}

}  // namespace geodem
