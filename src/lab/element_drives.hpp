// The drives of the element tests' loading programs (lab/run_element_test.hpp): each axis
// of the cell or box held at a stress or moved at a strain rate, and the stresses and void
// ratio the programs read.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "controllers/axial_strain_rate.hpp"
#include "controllers/cell_servo.hpp"
#include "controllers/stress_servo.hpp"
#include "measure/measurements.hpp"
#include "walls/lab_box.hpp"

namespace geodem {

// One axis of a loading step: a stress target, or a strain rate (compression positive).
struct AxisDrive {
  bool stress = false;
  double target = 0.0;
  double rate = 0.0;
};

// Installs the controllers that drive each axis as `drives` says, with the periodic cell's
// shear rate L_xn; the servos made at consolidation (lab/triaxial_controllers.hpp) keep their
// integral terms while their target stays.
template <int D>
void drive_axes(World<D>& w, const LabBox<D>& box, const std::array<AxisDrive, D>& drives,
                double shear_rate, std::vector<std::shared_ptr<Controller<D>>>& servos) {
  w.controllers.clear();
  if (box.periodic) {
    auto cell = std::static_pointer_cast<CellServo<D>>(servos[0]);
    for (int k = 0; k < D; ++k)
      cell->set_axis(k, {drives[k].stress, drives[k].target, -drives[k].rate});
    w.cell.vel_grad(0, D - 1) = shear_rate;
    w.controllers.push_back(cell);
    return;
  }
  for (int k = 0; k < D; ++k) {
    if (drives[k].stress) {
      auto servo = std::static_pointer_cast<StressServo<D>>(servos[static_cast<std::size_t>(k)]);
      servo->set_target(drives[k].target);
      w.controllers.push_back(servo);
    } else {
      w.controllers.push_back(std::make_shared<AxialStrainRate<D>>(box, k, drives[k].rate));
    }
  }
}

// The axial stress and the mean lateral stress (compression positive).
template <int D>
std::array<double, 2> axial_and_lateral(const World<D>& w, const LabBox<D>& box) {
  using Tensor = typename Dim<D>::Tensor;
  const Tensor sigma = box.periodic ? cell_stress(w) : Tensor::Zero().eval();
  const auto stress = [&](int k) { return box.periodic ? sigma(k, k) : box.stress(w, k); };
  double lateral = 0.0;
  for (int k = 0; k < D - 1; ++k) lateral += stress(k) / (D - 1);
  return {stress(D - 1), lateral};
}

template <class Lab>
double void_ratio(const Lab& lab) {
  const double n = lab.porosity();
  return n / (1.0 - n);
}

}  // namespace geodem
