// Strain-controlled loading: the hi wall of one axis moves towards the lo wall at
// strain_rate x the current box size (a constant true strain rate); the lo wall stays.
#pragma once

#include "walls/lab_box.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
class AxialStrainRate : public Controller<D> {
 public:
  AxialStrainRate(const LabBox<D>& box, int axis, double strain_rate)
      : box_(box), axis_(axis), rate_(strain_rate) {}
  bool walls_only() const override { return true; }
  void apply(World<D>& w) override {
    auto& top = w.walls[box_.hi[axis_]];
    top.velocity = (rate_ * box_.size(w)[axis_]) * top.normal;  // the normal points inwards
    w.walls[box_.lo[axis_]].velocity.setZero();
  }

 private:
  LabBox<D> box_;
  int axis_;
  double rate_;
};

}  // namespace geodem
