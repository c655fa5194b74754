// The state of an element test's loading program (lab/run_element_test.hpp) from the end of
// its consolidation on, saved in checkpoints, and the kinds' CSV columns.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/dim.hpp"
#include "base/state_archive.hpp"
#include "lab/element_test_results.hpp"
#include "lab/element_test_settings.hpp"

namespace geodem {

template <int D>
struct ElementTest {
  typename Dim<D>::Vec ref = Dim<D>::Vec::Zero();  // cell or box size after consolidation
  std::uint64_t stage = 0;  // stress step (isotropic, oedometer) or amplitude (cyclic)
  std::uint64_t turn = 0;   // cyclic: turning points passed at this amplitude
  double rate = 0.0;        // cyclic: this amplitude's axial strain rate (1/s) or q rate (Pa/s)
  double q_target = 0.0;    // cyclic, stress control: the ramped deviator target (Pa)
  double path = 0.0;        // cyclic: axial strain travelled at this amplitude
  double last_strain = 0.0, last_gamma = 0.0;  // cyclic: axial and shear strain a step ago
  double next_record = 0.0;                    // strain (shear, or travelled) of the next row
  double porosity0 = 0.0;
  double split = 0.0, plate0 = 0.0;  // direct shear: the split plane's and plate's heights
  StressSteps steps;                 // isotropic, oedometer: the points at rest
  ShearCurve curve;                  // simple shear
  CycleMeter loop;                   // cyclic: the loop under way
  std::vector<CycleResult> loops;    // cyclic: every loop, amplitude after amplitude
  std::string warning;

  template <class Archive>
  void visit(Archive& a) {
    a(ref), a(stage), a(turn), a(rate), a(q_target), a(path), a(last_strain), a(last_gamma),
        a(next_record), a(porosity0), a(split), a(plate0);
    a(steps.target), a(steps.sigma_axial), a(steps.sigma_lateral), a(steps.axial_strain);
    a(steps.volumetric_strain), a(steps.void_ratio);
    a(curve.shear_strain), a(curve.shear_stress), a(curve.normal_stress), a(curve.normal_strain);
    a(curve.phi_mobilised_deg), a(curve.void_ratio);
    loop.visit(a);
    std::uint64_t n = loops.size();
    a(n);
    loops.resize(n);
    for (auto& c : loops) c.visit(a);
    a(warning);
  }
};

inline std::vector<std::string> element_test_columns(LabKind kind) {
  switch (kind) {
    case LabKind::kSimpleShear:
      return {"test",
              "step",
              "time",
              "shear_strain",
              "normal_strain",
              "volumetric_strain",
              "normal_stress",
              "shear_stress",
              "stress_ratio",
              "sigma1",
              "sigma3",
              "phi_mobilised_deg",
              "p",
              "void_ratio",
              "coordination",
              "unbalanced"};
    case LabKind::kDirectShear:
      return {"test",         "step",          "time",         "displacement",
              "shear_stress", "normal_stress", "stress_ratio", "vertical_displacement",
              "void_ratio",   "coordination",  "unbalanced"};
    case LabKind::kCyclicTriaxial:
      return {"amplitude",
              "cycle",
              "step",
              "time",
              "axial_strain",
              "lateral_strain",
              "shear_strain",
              "sigma_axial",
              "sigma_lateral",
              "q",
              "p",
              "void_ratio",
              "unbalanced"};
    default:
      return {"stage",
              "step",
              "time",
              "target",
              "sigma_axial",
              "sigma_lateral",
              "p",
              "q",
              "axial_strain",
              "volumetric_strain",
              "void_ratio",
              "coordination",
              "unbalanced",
              "at_rest"};
  }
}

}  // namespace geodem
