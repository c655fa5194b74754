// Servo-controlled walls: the two walls normal to an axis move so that the stress on
// them reaches a target. The error is turned into the wall displacement that would
// cancel it if the contact stiffness stayed the same, e = (sigma - target) x area /
// (the walls' mean contact stiffness) (yade's TriaxialStressController); each step the
// walls move by gain x e + integral_gain x (sum of past e), a proportional-integral law:
// the integral term supplies the steady wall velocity a dilating or contracting sample
// needs, which a proportional law alone only gets from a steady stress error. The
// velocity is capped at max_strain_rate x the box size.
//
// The two walls always move by the same amount in opposite directions, so the box's
// centre stays where it is. Walls driven each by its own stiffness and its own integral
// sum end with sums that differ by a constant, a steady translation of the whole sample;
// a drifting sample defeats local damping (it acts on the sign of each grain's absolute
// velocity), and the unbalanced force then never falls to its tolerance.
#pragma once

#include <algorithm>
#include <cmath>

#include "base/state_archive.hpp"
#include "walls/lab_box.hpp"
#include "world/world.hpp"

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

  bool walls_only() const override { return true; }
  void apply(World<D>& w) override {
    const double sigma = box_.stress(w, axis_);
    const double area = box_.area(w, axis_);
    const double vmax = max_rate_ * box_.size(w)[axis_];
    auto& lo = w.walls[box_.lo[axis_]];
    auto& hi = w.walls[box_.hi[axis_]];
    // A move of u by both walls changes the mean of their stresses by the mean stiffness
    // times u, over the area.
    const double stiffness = 0.5 * (lo.stiffness + hi.stiffness);
    double v;  // outward speed of each wall: positive when the stress is above the target
    if (stiffness > 0.0) {
      const double e = (sigma - target_) * area / stiffness;
      // Anti-windup: the sum only grows while the walls are not at their speed limit.
      const double trial = (gain_ * e + integral_gain_ * (sum_ + e)) / w.dt;
      if (std::abs(trial) < vmax) sum_ += e;
      v = (gain_ * e + integral_gain_ * sum_) / w.dt;
    } else {
      v = sigma < target_ ? -vmax : 0.0;  // no contact yet: close in
    }
    v = std::clamp(v, -vmax, vmax);
    lo.velocity = -v * lo.normal;
    hi.velocity = -v * hi.normal;
  }

 private:
  LabBox<D> box_;
  int axis_;
  double target_, gain_, integral_gain_, max_rate_;
  double sum_ = 0.0;  // accumulated displacement errors (m)
};

}  // namespace geodem
