// Mixed stress and strain control of a periodic cell (yade's PeriTriaxController, PFC's
// periodic servo): each diagonal component of the velocity gradient L is either a given
// strain rate, or set every step so that the cell's average stress on that axis reaches a
// target. Off-diagonal components (shear) are left as they are set.
//
// Under stress control the step's strain increment is gain x (sigma_kk - target) / K_k, with
// K_k = sum kn (d_k n_k)^2 / V the stiffness of the packing against a homogeneous strain of
// that component (what an affine strain would change the stress by): a gain below one
// corrects part of the error each step, so the grains' inertia does not make it overshoot.
// Without contacts the cell closes (or opens) at the largest rate.
#pragma once

#include <algorithm>
#include <array>

#include "measure/measurements.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
class CellServo : public Controller<D> {
 public:
  struct Axis {
    bool stress_controlled = false;
    double target = 0.0;       // Pa, compression positive (stress control)
    double strain_rate = 0.0;  // 1/s, extension positive (strain control)
  };

  CellServo(const std::array<Axis, D>& axes, double max_strain_rate, double gain)
      : axes_(axes), max_rate_(max_strain_rate), gain_(gain) {}

  void apply(World<D>& w) override {
    const auto sigma = cell_stress(w);
    const double volume = w.cell.volume();
    for (int k = 0; k < D; ++k) {
      const Axis& a = axes_[k];
      double rate = a.strain_rate;
      if (a.stress_controlled) {
        const double error = sigma(k, k) - a.target;  // > 0: too compressed, extend
        const double stiffness = w.cell_stiffness[k] / volume;
        rate = stiffness > 0.0 ? gain_ * error / (stiffness * w.dt)
                               : (error > 0.0 ? max_rate_ : -max_rate_);
        rate = std::clamp(rate, -max_rate_, max_rate_);
      }
      w.cell.vel_grad(k, k) = rate;
    }
  }

  const std::array<Axis, D>& axes() const { return axes_; }
  void set_axis(int k, const Axis& a) { axes_[k] = a; }

 private:
  std::array<Axis, D> axes_;
  double max_rate_;
  double gain_;
};

}  // namespace geodem
