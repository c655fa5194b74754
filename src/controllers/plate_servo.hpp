// A loading plate held at a normal stress (the normal load of a shear box): the plane
// wall moves along its normal so that the grains' pressure on it reaches the target.
// Proportional-integral law, as the lab box servo (stress_servo.hpp): the error becomes
// the displacement that would cancel it at the current contact stiffness; each step the
// plate moves by gain x error + integral_gain x (sum of past errors). The integral term
// supplies the steady velocity of a sample that dilates or contracts while it is sheared,
// which a proportional law only gets from a steady stress error. The speed is capped.
// With `count_dashpots`, the error is turned into a displacement at the stiffness the plate
// meets within one step, k + c / dt (c: its contacts' normal dashpots): a plate whose speed
// flips each step at its cap would otherwise see the dashpots' force flip with it, a
// limit cycle that holds it off its target.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "base/state_archive.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
class PlateServo : public Controller<D> {
 public:
  PlateServo(std::size_t wall, double target, double max_speed, double gain = 0.5,
             double integral_gain = 0.05, bool count_dashpots = false)
      : wall_(wall),
        target_(target),
        vmax_(max_speed),
        gain_(gain),
        integral_gain_(integral_gain),
        count_dashpots_(count_dashpots) {}

  std::size_t wall() const { return wall_; }
  bool wall_removed(std::size_t index) override {
    if (index == wall_) return true;
    if (wall_ > index) --wall_;
    return false;
  }
  double target() const { return target_; }
  void set_target(double t) { target_ = t; }
  // Pressure the grains exert on the plate (Pa).
  double pressure(const World<D>& w) const { return w.walls[wall_].normal_stress(); }
  void save_state(StateWriter& out) const override {
    out(target_), out(vmax_), out(sum_), out(stiffness_);
  }
  void load_state(StateReader& in) override { in(target_), in(vmax_), in(sum_), in(stiffness_); }

  bool walls_only() const override { return true; }
  void apply(World<D>& w) override {
    auto& wall = w.walls[wall_];
    // A plate that just lost its contacts (it rebounded, or the soil below it dilated and
    // then settled) comes back at the last contact stiffness it saw: at full speed it
    // would hit the grains far too hard and bounce off again, a limit cycle.
    // Its integral term is dropped then too: it holds the steady speed of a plate that
    // follows the soil, which a plate out of contact no longer does.
    if (wall.stiffness > 0.0)
      stiffness_ = wall.stiffness + (count_dashpots_ ? wall.dashpot / w.dt : 0.0);
    else
      sum_ = 0.0;
    double v;  // speed along the plate's normal, towards the grains
    if (stiffness_ > 0.0) {
      const double e = (target_ - wall.normal_stress()) * wall.area / stiffness_;
      // Anti-windup: the sum only grows while the plate is below its speed cap.
      const double trial = (gain_ * e + integral_gain_ * (sum_ + e)) / w.dt;
      if (std::abs(trial) < vmax_) sum_ += e;
      v = (gain_ * e + integral_gain_ * sum_) / w.dt;
    } else {
      v = vmax_;  // never touched yet: come down
    }
    wall.velocity = std::clamp(v, -vmax_, vmax_) * wall.normal;
  }

 private:
  std::size_t wall_;
  double target_, vmax_, gain_, integral_gain_;
  bool count_dashpots_;
  double sum_ = 0.0;        // accumulated displacement errors (m)
  double stiffness_ = 0.0;  // the plate's contact stiffness when it last touched (N/m)
};

}  // namespace geodem
