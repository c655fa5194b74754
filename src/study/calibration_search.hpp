// The micro-macro search of kind = "calibrate" (docs/studies.md, "Calibration").
// Each micro parameter is matched to the macro property it governs most, as the
// micro-macro relations of DEM soils say (Young's modulus ~ contact modulus, Poisson's
// ratio ~ kt/kn, peak friction ~ contact friction, cohesion ~ bond strength, residual
// friction ~ rolling resistance), and all are updated together after each evaluation
// by a one-dimensional secant step each: a quasi-Newton method with a diagonal Jacobian,
// in variables where the relation is nearly linear (log modulus, log kt/kn). A pure
// class: tested against synthetic soils with known micro-macro relations.
#pragma once

#include <vector>

#include "study/study_settings.hpp"

namespace geodem {

struct MicroParameters {
  double young = 0.0, kt_over_kn = 0.0, friction_deg = 0.0;
  double bond_strength = 0.0;  // normal_cohesion; shear_cohesion keeps its ratio
  double rolling_friction = 0.0;
};

struct MacroValues {
  double phi_peak_deg = 0.0, cohesion = 0.0, young_modulus = 0.0, poisson_ratio = 0.0,
         phi_residual_deg = 0.0;
};

struct SearchTolerances {
  double phi_deg = 0.5, cohesion = 500.0, young = 0.05, poisson = 0.02;
};

// Root finding of y(x) = target from successive evaluations: a Newton step with the
// least-squares slope of the last four points (the secant when two are known), a
// default slope until then (or when noise gives a slope of the wrong sign or near
// zero), a step limit and bounds.
class SecantStep {
 public:
  SecantStep(double default_slope, double max_step, double lo, double hi)
      : slope0_(default_slope), max_step_(max_step), lo_(lo), hi_(hi) {}
  double next(double x, double y, double target);

 private:
  double slope0_, max_step_, lo_, hi_;
  std::vector<double> xs_, ys_;
};

class CalibrationSearch {
 public:
  CalibrationSearch(const CalibrationTargets& targets, const SearchTolerances& tolerances,
                    const MicroParameters& start);
  const MicroParameters& current() const { return p_; }
  // Which targets are searched.
  bool searches_bonds() const { return bonds_; }
  // Records the macro values of current() and moves to the next parameters. Returns
  // true (and stays) when every target is met.
  bool record(const MacroValues& m);
  bool met(const MacroValues& m) const;
  // Largest miss relative to its tolerance (< 1: all met).
  double miss(const MacroValues& m) const;

 private:
  CalibrationTargets t_;
  SearchTolerances tol_;
  MicroParameters p_;
  bool bonds_;
  SecantStep friction_, young_, ktkn_, bond_, rolling_;
};

}  // namespace geodem
