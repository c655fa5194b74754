// A plate on a free surface held at a pressure (a surcharge): the plane wall moves
// along its normal so that the grains' force on it equals pressure x area. Same law as
// the lab box servo (stress_servo.hpp): the displacement that would cancel the error at
// the current contact stiffness, times a gain, each step; the speed is capped.
#pragma once

#include <algorithm>

#include "base/state_archive.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
class SurfacePressure : public Controller<D> {
 public:
  SurfacePressure(std::size_t wall, double pressure, double max_speed, double gain = 0.3)
      : wall_(wall), pressure_(pressure), vmax_(max_speed), gain_(gain) {}

  // Pressure the grains exert on the plate (Pa).
  double pressure(const World<D>& w) const { return w.walls[wall_].normal_stress(); }
  // The speed cap is set from the time step when the plate is placed: a run rebuilt
  // for resuming takes it from the checkpoint.
  void save_state(StateWriter& out) const override { out(vmax_); }
  void load_state(StateReader& in) override { in(vmax_); }

  bool walls_only() const override { return true; }
  void apply(World<D>& w) override {
    auto& wall = w.walls[wall_];
    double v;  // speed along the plate's normal, towards the grains
    if (wall.stiffness > 0.0) {
      v = gain_ * (pressure_ - wall.normal_stress()) * wall.area / wall.stiffness / w.dt;
    } else {
      v = vmax_;  // not touching yet: come down
    }
    wall.velocity = std::clamp(v, -vmax_, vmax_) * wall.normal;
  }

 private:
  std::size_t wall_;
  double pressure_, vmax_, gain_;
};

}  // namespace geodem
