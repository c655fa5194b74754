// What an engineer reads from interface shear tests (docs/lab_tests.md, "Interface
// shear"): peak and residual shear strength of each test, the interface shear
// stiffness, dilation, and the Mohr-Coulomb envelope tau = adhesion + sigma_n tan(delta)
// over several normal stresses. Pure functions over the tests' curves, tested on
// synthetic curves with known answers.
#pragma once

#include <vector>

namespace geodem {

struct InterfaceCurve {
  std::vector<double> displacement;  // relative slip of the sheet under the box (m)
  std::vector<double> shear;         // shear stress on the sheet (Pa)
  std::vector<double> normal;        // normal stress on the sheet (Pa)
  std::vector<double> dilation;      // rise of the loading plate since the start (m)
};

struct InterfaceTest {
  double normal_stress = 0.0;  // mean over the test (Pa)
  double peak_shear = 0.0;     // Pa
  double displacement_at_peak = 0.0;
  double peak_ratio = 0.0;          // tau / sigma_n at the peak
  double normal_at_peak = 0.0;      // sigma_n at the peak (Pa)
  double residual_normal = 0.0;     // mean sigma_n over the residual range (Pa)
  double residual_shear = 0.0;      // mean over the residual range (Pa)
  double residual_ratio = 0.0;      // mean tau / mean sigma_n over it
  double shear_stiffness = 0.0;     // secant to half the peak shear stress (Pa/m)
  double dilation_max = 0.0;        // m
  double dilation_end = 0.0;        // m
  double dilation_angle_deg = 0.0;  // atan of the plate's rise per slip around the peak
};

// residual_from: fraction of the largest displacement from which the residual state is
// averaged (the last 20 % by default).
InterfaceTest interface_test(const InterfaceCurve& c, double residual_from = 0.8);

struct InterfaceEnvelope {
  double friction_deg = 0.0;  // delta: atan of the slope of tau against sigma_n
  double adhesion = 0.0;      // intercept (Pa)
  double r2 = 0.0;
  bool fitted = false;  // two tests or more at distinct normal stresses
};

// Least-squares line tau = adhesion + sigma_n tan(delta). With a single test the line
// goes through the origin (adhesion 0).
InterfaceEnvelope fit_interface_envelope(const std::vector<double>& normal,
                                         const std::vector<double>& shear);

}  // namespace geodem
