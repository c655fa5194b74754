// Mixed stress and strain control of a periodic cell (yade's PeriTriaxController, PFC's
// periodic servo): each diagonal component of the velocity gradient L is either a given
// strain rate, or set every step so that the cell's average stress on that axis reaches a
// target. Off-diagonal components (shear) are left as they are set.
//
// Under stress control the error is turned into the strain that would cancel it if the
// packing deformed affinely, e = (sigma_kk - target) / K_k, with K_k = sum kn (d_k n_k)^2 / V
// the stiffness of the packing against a homogeneous strain of that component; the step's
// strain increment is gain x e + integral_gain x (sum of past e) (by default half the gain),
// a proportional-integral law as the walls' StressServo: a gain below one corrects part of the
// error each step, so that the grains' inertia does not make it overshoot, and the integral term
// supplies the steady rate that a dilating or contracting sample needs, which the proportional term
// alone only gets from a steady error. Without contacts the cell closes (or opens) at the largest
// rate.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "base/state_archive.hpp"
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

  CellServo(const std::array<Axis, D>& axes, double max_strain_rate, double gain,
            double integral_gain = -1.0)
      : axes_(axes),
        max_rate_(max_strain_rate),
        gain_(gain),
        integral_gain_(integral_gain < 0.0 ? 0.5 * gain : integral_gain) {
    sum_.fill(0.0);
  }

  void apply(World<D>& w) override {
    const auto sigma = cell_stress(w);
    const double volume = w.cell.volume();
    for (int k = 0; k < D; ++k) {
      const Axis& a = axes_[k];
      double rate = a.strain_rate;
      if (a.stress_controlled) {
        const double error = sigma(k, k) - a.target;  // > 0: too compressed, extend
        const double stiffness = w.cell_stiffness[k] / volume;
        if (stiffness > 0.0) {
          const double e = error / stiffness;
          // Anti-windup: the sum only grows while the rate is below its limit.
          const double trial = (gain_ * e + integral_gain_ * (sum_[k] + e)) / w.dt;
          if (std::abs(trial) < max_rate_) sum_[k] += e;
          rate = (gain_ * e + integral_gain_ * sum_[k]) / w.dt;
        } else {
          rate = error > 0.0 ? max_rate_ : -max_rate_;
        }
        rate = std::clamp(rate, -max_rate_, max_rate_);
      }
      w.cell.vel_grad(k, k) = rate;
    }
  }

  // A new stress target (or a change of control) starts the axis's integral term afresh; a
  // new strain rate, or the same target again, keeps it.
  void set_axis(int k, const Axis& a) {
    const Axis& old = axes_[k];
    if (a.stress_controlled != old.stress_controlled || a.target != old.target) sum_[k] = 0.0;
    axes_[k] = a;
  }
  // Moves a stress-controlled axis's target (a ramp), keeping its integral term.
  void set_target(int k, double target) { axes_[k].target = target; }
  void save_state(StateWriter& out) const override {
    for (const auto& a : axes_) out(a.stress_controlled), out(a.target), out(a.strain_rate);
    out(sum_);
  }
  void load_state(StateReader& in) override {
    for (auto& a : axes_) in(a.stress_controlled), in(a.target), in(a.strain_rate);
    in(sum_);
  }

 private:
  std::array<Axis, D> axes_;
  double max_rate_;
  double gain_, integral_gain_;
  std::array<double, D> sum_;  // accumulated strain errors per axis
};

}  // namespace geodem
