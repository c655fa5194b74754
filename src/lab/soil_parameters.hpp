// What a geotechnical engineer reads from a compression test: peak and residual
// strength, friction angles, elastic constants, dilatancy, and the Mohr-Coulomb
// envelope of several tests. Pure functions over the test's history (compression
// positive, volumetric strain positive in contraction), so they are tested on
// synthetic curves with known answers.
#pragma once

#include <vector>

namespace geodem {

struct CompressionCurve {
  int dimension = 3;                 // 3: triaxial (sigma2 = sigma3); 2: biaxial (plane strain)
  std::vector<double> axial_strain;  // epsilon_1
  std::vector<double> volumetric_strain;
  std::vector<double> sigma1, sigma3;
};

struct SoilParameters {
  double peak_q = 0.0;  // max of sigma1 - sigma3 (Pa)
  double axial_strain_at_peak = 0.0;
  double phi_peak_deg = 0.0;      // sin(phi) = (s1 - s3)/(s1 + s3) at the peak
  double phi_residual_deg = 0.0;  // same, averaged over the last fifth of the strain range
  double young_modulus = 0.0;     // E50: secant to half the peak q (Pa)
  double poisson_ratio = 0.0;     // from the strains up to half the peak q
  double dilatancy_deg = 0.0;     // sin(psi) = -d(eps_v)/(2 d(eps_1) - d(eps_v)) around the peak
};

SoilParameters soil_parameters(const CompressionCurve& c);

// Friction angle (degrees) from principal stresses: sin(phi) = (s1 - s3)/(s1 + s3).
double mobilised_friction_deg(double sigma1, double sigma3);

struct MohrCoulomb {
  double cohesion = 0.0;  // Pa
  double phi_deg = 0.0;
};

// Least-squares fit of the peak states: in (p', q') = ((s1 + s3)/2, (s1 - s3)/2)
// the envelope is q' = c cos(phi) + p' sin(phi). Needs two tests or more.
MohrCoulomb fit_mohr_coulomb(const std::vector<double>& sigma1_peak,
                             const std::vector<double>& sigma3_peak);

}  // namespace geodem
