// The controllers of each phase of the triaxial test (lab/run_triaxial.cpp), with walls or in
// a periodic cell:
// - preparation: radius growth to the compaction stress, the box or cell fixed;
// - consolidation: every axis held at the confining stress, by one servo per wall axis
//   (StressServo) or by the cell servo (CellServo);
// - compression: the axial strain rate imposed (AxialStrainRate, or the cell's axial
//   velocity gradient), the lateral axes still at the confining stress; undrained, the
//   lateral axes extend at the rate that keeps the volume constant instead (-rate / (D - 1)
//   each: the rates sum to zero).
// A test's servos are made at its consolidation and kept through its compression, so that
// their integral terms carry over.
#pragma once

#include <memory>
#include <vector>

#include "controllers/axial_strain_rate.hpp"
#include "controllers/cell_servo.hpp"
#include "controllers/radius_growth.hpp"
#include "controllers/stress_servo.hpp"
#include "lab/triaxial_settings.hpp"
#include "walls/lab_box.hpp"

namespace geodem {

enum class TriaxialStage { kPreparation, kConsolidation, kCompression, kDone };

// The cell servo's largest strain rate, as a multiple of the test's axial strain rate: enough
// to follow the stress during compression and to reconsolidate in a few strain units.
inline constexpr double kCellServoRateFactor = 5.0;

template <int D>
void install_triaxial_controllers(World<D>& w, const LabBox<D>& box, const TriaxialSettings& s,
                                  TriaxialStage stage, double sigma3, bool new_servos,
                                  std::vector<std::shared_ptr<Controller<D>>>& servos) {
  w.controllers.clear();
  if (stage == TriaxialStage::kPreparation) {
    w.controllers.push_back(std::make_shared<RadiusGrowth<D>>(
        box, s.compaction_stress, s.max_multiplier, s.final_max_multiplier));
    return;
  }
  if (stage == TriaxialStage::kDone) return;
  constexpr int kAxial = D - 1;
  if (box.periodic) {
    using Axis = typename CellServo<D>::Axis;
    if (new_servos) {
      std::array<Axis, D> axes;
      for (auto& a : axes) a = Axis{true, sigma3, 0.0};
      servos = {
          std::make_shared<CellServo<D>>(axes, kCellServoRateFactor * s.strain_rate, s.servo_gain)};
    }
    auto cell = std::static_pointer_cast<CellServo<D>>(servos[0]);
    if (stage == TriaxialStage::kCompression) {
      cell->set_axis(kAxial, Axis{false, 0.0, -s.strain_rate});
      if (s.undrained)
        for (int k = 0; k < kAxial; ++k)
          cell->set_axis(k, Axis{false, 0.0, s.strain_rate / (D - 1)});
    }
    w.controllers.push_back(cell);
    return;
  }
  if (new_servos) {
    servos.clear();
    for (int k = 0; k < D; ++k)
      servos.push_back(std::make_shared<StressServo<D>>(box, k, sigma3, s.servo_gain));
  }
  if (stage == TriaxialStage::kCompression) {
    // Axial wall strain-controlled, lateral walls servo-controlled (drained) or moved out at
    // the constant-volume rate (undrained).
    for (int k = 0; k < kAxial; ++k)
      if (s.undrained) {
        w.controllers.push_back(
            std::make_shared<AxialStrainRate<D>>(box, k, -s.strain_rate / (D - 1)));
      } else {
        w.controllers.push_back(servos[static_cast<std::size_t>(k)]);
      }
    w.controllers.push_back(std::make_shared<AxialStrainRate<D>>(box, kAxial, s.strain_rate));
  } else {
    w.controllers.assign(servos.begin(), servos.end());
  }
}

}  // namespace geodem
