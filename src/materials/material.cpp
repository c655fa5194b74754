#include "materials/material.hpp"

#include <algorithm>
#include <stdexcept>

namespace geodem {

PairLaw combine(const Material& a, const Material& b) {
  if (a.law != b.law)
    throw std::invalid_argument("materials '" + a.name + "' and '" + b.name +
                                "' use different contact laws; give the pair explicitly");
  PairLaw p;
  p.law = a.law;
  p.mu = std::min(a.friction, b.friction);
  const double e = std::min(a.restitution, b.restitution);
  p.beta = damping_ratio(e);
  p.tangential_damping = a.tangential_damping && b.tangential_damping;
  p.roll_mu = std::min(a.rolling_friction, b.rolling_friction);
  p.twist_mu = std::min(a.twisting_friction, b.twisting_friction);
  p.roll_kr = std::min(a.rolling_stiffness, b.rolling_stiffness);
  p.bond_tension = std::min(a.normal_cohesion, b.normal_cohesion);
  p.bond_shear = std::min(a.shear_cohesion, b.shear_cohesion);
  p.bond_as_force = a.cohesion_as_force && b.cohesion_as_force;
  if (p.cohesive() && a.law != LawKind::kLinear)
    throw std::invalid_argument("materials '" + a.name + "' and '" + b.name +
                                "': contact cohesion needs the linear law");
  if (a.law == LawKind::kLinear) {
    if (a.kn > 0.0 || b.kn > 0.0) {
      // Constant stiffness: springs in series when both give one.
      const double ka = a.kn > 0.0 ? a.kn : b.kn, kb = b.kn > 0.0 ? b.kn : a.kn;
      p.constant_stiffness = true;
      p.kn = (ka == kb) ? ka : ka * kb / (ka + kb);
      const double kta = a.kt >= 0.0 ? a.kt : a.kt_over_kn * ka;
      const double ktb = b.kt >= 0.0 ? b.kt : b.kt_over_kn * kb;
      p.kt = (kta == ktb) ? kta : (kta + ktb > 0.0 ? kta * ktb / (kta + ktb) : 0.0);
    } else {
      p.e1r = a.young;
      p.e2r = b.young;
      p.kt_over_kn = 0.5 * (a.kt_over_kn + b.kt_over_kn);
    }
  } else {
    p.estar = 1.0 / ((1 - a.poisson * a.poisson) / a.young + (1 - b.poisson * b.poisson) / b.young);
    p.gstar = 1.0 / (2 * (2 - a.poisson) * (1 + a.poisson) / a.young +
                     2 * (2 - b.poisson) * (1 + b.poisson) / b.young);
    p.hertz_damp = PairLaw::hertz_damping(p.beta);
  }
  return p;
}

}  // namespace geodem
