// The controllers of each stage of the triaxial kind and its element tests
// (lab/run_triaxial.cpp): the triaxial test's (lab/triaxial_controllers.hpp); an element
// test's program drives the consolidation's servos (lab/run_element_test.hpp); the direct
// shear box consolidates under its plate alone, the sides of the box fixed.
#pragma once

#include <memory>

#include "controllers/plate_servo.hpp"
#include "lab/run_element_test.hpp"
#include "lab/triaxial_controllers.hpp"

namespace geodem {

// The plate servo's proportional and integral gains (controllers/plate_servo.hpp).
inline constexpr double kShearBoxPlateGain = 0.5, kShearBoxPlateIntegralGain = 0.05;

template <class Lab>
void install_lab_controllers(Lab& lab, TriaxialStage stage, bool new_servos) {
  constexpr int D = Lab::kDim;
  const auto& s = lab.s;
  const bool box_stage =
      stage == TriaxialStage::kConsolidation || stage == TriaxialStage::kCompression;
  if (s.kind == LabKind::kDirectShear && box_stage) {
    if (new_servos) {
      const double height = lab.box.size(lab.w)[D - 1];
      lab.servos = {std::make_shared<PlateServo<D>>(
          lab.box.hi[D - 1], lab.sigma3(), kCellServoRateFactor * s.strain_rate * height,
          kShearBoxPlateGain, kShearBoxPlateIntegralGain)};
      lab.w.walls[lab.box.hi[D - 1]].area = lab.box.area(lab.w, D - 1);
    }
    lab.w.controllers = {lab.servos[0]};
    if (stage == TriaxialStage::kCompression) install_element_drives(lab);
    return;
  }
  if (s.kind == LabKind::kTriaxial || stage != TriaxialStage::kCompression) {
    install_triaxial_controllers(lab.w, lab.box, s, stage, lab.sigma3(), new_servos, lab.servos);
    return;
  }
  install_triaxial_controllers(lab.w, lab.box, s, TriaxialStage::kConsolidation, lab.sigma3(),
                               new_servos, lab.servos);
  install_element_drives(lab);
}

}  // namespace geodem
