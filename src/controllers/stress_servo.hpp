// Servo-controlled walls: the two walls normal to an axis move so that the stress on
// them reaches a target. Each step a wall moves by gain x (sigma - target) x area /
// (its contact stiffness), the displacement that would cancel the error if the
// stiffness stayed the same (yade's TriaxialStressController), capped at a velocity of
// max_strain_rate x the box size; the velocity is smoothed over a few steps.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/world.hpp"
#include "lab/lab_box.hpp"

namespace geodem {

template <int D>
class StressServo : public Controller<D> {
 public:
  StressServo(const LabBox<D>& box, int axis, double target, double gain = 0.5,
              double max_strain_rate = 1.0, double smoothing = 0.5)
      : box_(box),
        axis_(axis),
        target_(target),
        gain_(gain),
        max_rate_(max_strain_rate),
        smoothing_(smoothing) {}

  void set_target(double t) { target_ = t; }
  double target() const { return target_; }

  void apply(World<D>& w) override {
    const double sigma = box_.stress(w, axis_);
    const double area = box_.area(w, axis_);
    const double vmax = max_rate_ * box_.size(w)[axis_];
    for (std::size_t idx : {box_.lo[axis_], box_.hi[axis_]}) {
      auto& wall = w.walls[idx];
      // Outward speed: positive when the stress is above the target.
      double v;
      if (wall.stiffness > 0.0)
        v = gain_ * (sigma - target_) * area / wall.stiffness / w.dt;
      else
        v = sigma < target_ ? -vmax : 0.0;  // no contact yet: close in
      v = std::clamp(v, -vmax, vmax);
      const double previous = -wall.velocity.dot(wall.normal);
      const double smoothed = smoothing_ * previous + (1.0 - smoothing_) * v;
      wall.velocity = -smoothed * wall.normal;
    }
  }

 private:
  LabBox<D> box_;
  int axis_;
  double target_, gain_, max_rate_, smoothing_;
};

}  // namespace geodem
