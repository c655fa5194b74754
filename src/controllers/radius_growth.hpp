// Compaction by radius growth (yade's TriaxialStressController with internal
// compaction): the walls stay fixed and every grain radius is multiplied by
// m = 1 + (target - mean stress)/target x (max_multiplier - 1); once the mean stress
// has reached the target, the smaller final_max_multiplier is used. Masses scale as
// m^D and inertias as m^(D+2); contact stiffnesses follow since they are computed
// from the radii. The neighbour list's displacement bound takes the growth in.
#pragma once

#include <algorithm>
#include <cmath>

#include "base/state_archive.hpp"
#include "walls/lab_box.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
class RadiusGrowth : public Controller<D> {
 public:
  RadiusGrowth(const LabBox<D>& box, double target, double max_multiplier,
               double final_max_multiplier, int interval = 10)
      : box_(box),
        target_(target),
        max_mult_(max_multiplier),
        final_mult_(final_max_multiplier),
        interval_(interval) {}

  void apply(World<D>& w) override {
    if (w.step % static_cast<std::uint64_t>(interval_) != 0) return;
    const double sigma = box_.mean_stress(w);
    if (sigma >= target_) reached_ = true;
    const double limit = reached_ ? final_mult_ : max_mult_;
    const double m =
        std::clamp(1.0 + (target_ - sigma) / target_ * (limit - 1.0), 2.0 - limit, limit);
    scale(w, m);
  }
  bool reached() const { return reached_; }
  void save_state(StateWriter& out) const override { out(reached_); }
  void load_state(StateReader& in) override { in(reached_); }

  // Multiplies every grain radius by m.
  static void scale(World<D>& w, double m) {
    auto& P = w.particles;
    double rmax = 0.0;
    const double mass_factor = std::pow(m, D), inertia_factor = std::pow(m, D + 2);
    for (std::size_t i = 0; i < P.size(); ++i) {
      P.radius[i] *= m;
      P.inv_mass[i] /= mass_factor;
      P.inv_inertia[i] /= inertia_factor;
      rmax = std::max(rmax, P.radius[i]);
    }
    // Clumps grow homothetically about their centres of mass.
    // A member's centre moves by |offset| (m - 1) too: the bound takes that in.
    for (std::size_t i = 0; i < P.body_offset.size(); ++i) {
      P.body_offset[i] *= m;
      rmax = std::max(rmax, P.radius[i] + P.body_offset[i].norm());
    }
    w.clumps.scale(m);
    // (a decomposed world: the whole domain's largest, so that every rank rebuilds together
    // and as one process would)
    if (w.domain) rmax = -w.domain->min_over_ranks(-rmax);
    // Gaps close by at most (r_i + r_j)(m - 1): counts as a displacement of rmax (m - 1).
    if (m > 1.0) w.radius_growth += rmax * (m - 1.0) / m;
  }

 private:
  LabBox<D> box_;
  double target_, max_mult_, final_mult_;
  int interval_;
  bool reached_ = false;
};

}  // namespace geodem
