// Servo-controlled walls: the two walls normal to an axis move so that the stress on
// them reaches a target. The error is turned into the wall displacement that would
// cancel it if the contact stiffness stayed the same, e = (sigma - target) x area /
// (the wall's contact stiffness) (yade's TriaxialStressController); each step the wall
// moves by gain x e + integral_gain x (sum of past e), a proportional-integral law: the
// integral term supplies the steady wall velocity a dilating or contracting sample
// needs, which a proportional law alone only gets from a steady stress error. The
// velocity is capped at max_strain_rate x the box size.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/world.hpp"
#include "io/state_archive.hpp"
#include "lab/lab_box.hpp"

namespace geodem {

template <int D>
class StressServo : public Controller<D> {
 public:
  StressServo(const LabBox<D>& box, int axis, double target, double gain = 0.5,
              double integral_gain = 0.1, double max_strain_rate = 1.0)
      : box_(box),
        axis_(axis),
        target_(target),
        gain_(gain),
        integral_gain_(integral_gain),
        max_rate_(max_strain_rate) {}

  void set_target(double t) { target_ = t; }
  double target() const { return target_; }
  void save_state(StateWriter& out) const override { out(target_), out(sum_); }
  void load_state(StateReader& in) override { in(target_), in(sum_); }

  void apply(World<D>& w) override {
    const double sigma = box_.stress(w, axis_);
    const double area = box_.area(w, axis_);
    const double vmax = max_rate_ * box_.size(w)[axis_];
    for (int side = 0; side < 2; ++side) {
      auto& wall = w.walls[side == 0 ? box_.lo[axis_] : box_.hi[axis_]];
      // Outward speed: positive when the stress is above the target.
      double v;
      if (wall.stiffness > 0.0) {
        const double e = (sigma - target_) * area / wall.stiffness;
        // Anti-windup: the sum only grows while the wall is not at its speed limit.
        const double trial = (gain_ * e + integral_gain_ * (sum_[side] + e)) / w.dt;
        if (std::abs(trial) < vmax) sum_[side] += e;
        v = (gain_ * e + integral_gain_ * sum_[side]) / w.dt;
      } else {
        v = sigma < target_ ? -vmax : 0.0;  // no contact yet: close in
      }
      v = std::clamp(v, -vmax, vmax);
      wall.velocity = -v * wall.normal;
    }
  }

 private:
  LabBox<D> box_;
  int axis_;
  double target_, gain_, integral_gain_, max_rate_;
  double sum_[2] = {0.0, 0.0};  // accumulated displacement errors of the lo and hi walls
};

}  // namespace geodem
