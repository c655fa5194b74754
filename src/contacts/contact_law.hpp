// Contact laws as plain inline functions over one contact: no virtual calls.
// Conventions: n is the unit normal from body 1 to body 2, delta > 0 the overlap,
// vrel the velocity of body 2's surface minus body 1's at the contact point.
// The returned vector is the force exerted by body 1 on body 2 (repulsive along +n);
// body 1 receives its opposite. `spring` holds the tangential force history.
#pragma once

#include <cmath>
#include <limits>

#include "base/dim.hpp"
#include "contacts/neighbour_list.hpp"
#include "materials/material.hpp"

namespace geodem {

struct NormalResult {
  double fn;  // normal force magnitude (positive: repulsive)
  double kt;  // tangential stiffness to use this step
  double cn;  // normal viscous coefficient (N s/m), 0 without damping
};

// Each law's formulas in one place: the normal force with its dashpot, the stiffnesses the
// time step and the servos need, the stored energy, and how a flat wall enters (its
// partner radius). r1, r2 are radii (r2 = partner_radius for a wall), inv_msum = 1/m1 +
// 1/m2 (m* = 1/inv_msum; 0: no dashpot), delta > 0 the overlap, vn the normal speed.

// Linear spring-dashpot (Cundall-Strack; LIGGGHTS/LAMMPS "hooke"): fn = kn delta - cn vn,
// cn = 2 beta sqrt(kn m*), kt from kn (PairLaw::linear_kn / linear_kt).
struct LinearLaw {
  // A wall as a grain of equal radius: kn = 2 E1 E2 r / (E1 + E2).
  static double partner_radius(double r) { return r; }
  [[gnu::always_inline]] static double dashpot(const PairLaw& p, double kn, double inv_msum) {
    return (p.beta > 0.0 && inv_msum > 0.0) ? 2.0 * p.beta * std::sqrt(kn / inv_msum) : 0.0;
  }
  [[gnu::always_inline]] static NormalResult normal(const PairLaw& p, double r1, double r2,
                                                    double inv_msum, double delta, double vn) {
    const double kn = p.linear_kn(r1, r2);
    const double cn = dashpot(p, kn, inv_msum);
    return {kn * delta - cn * vn, p.linear_kt(kn), cn};
  }
  static double normal_stiffness(const PairLaw& p, double r1, double r2) {
    return p.linear_kn(r1, r2);
  }
  // The spring's elastic energy fn^2 / (2 kn).
  static double energy(const PairLaw& p, double r1, double r2, double fn) {
    return 0.5 * fn * fn / p.linear_kn(r1, r2);
  }
};

// Hertz-Mindlin without slip (LIGGGHTS/LAMMPS "hertz"): fn = 4/3 E* sqrt(R*) delta^1.5 - cn
// vn, kt = 8 G* a with a = sqrt(R* delta), cn = hertz_damp sqrt(2 E* a m*) (Tsuji's form).
struct HertzLaw {
  // A flat wall has an infinite radius of curvature: R* = r.
  static double partner_radius(double) { return std::numeric_limits<double>::infinity(); }
  static double reduced_radius(double r1, double r2) {
    return std::isinf(r2) ? r1 : r1 * r2 / (r1 + r2);
  }
  [[gnu::always_inline]] static double dashpot(const PairLaw& p, double a, double inv_msum) {
    return (p.hertz_damp > 0.0 && inv_msum > 0.0)
               ? p.hertz_damp * std::sqrt(2.0 * p.estar * a / inv_msum)
               : 0.0;
  }
  [[gnu::always_inline]] static NormalResult normal(const PairLaw& p, double r1, double r2,
                                                    double inv_msum, double delta, double vn) {
    const double a = std::sqrt(reduced_radius(r1, r2) * delta);  // contact radius
    const double cn = dashpot(p, a, inv_msum);
    return {4.0 / 3.0 * p.estar * a * delta - cn * vn, 8.0 * p.gstar * a, cn};
  }
  // dfn/ddelta = 2 E* a = 3/2 fn / delta (elastic part).
  static double normal_stiffness(double fn, double delta) { return 1.5 * fn / delta; }
  static double tangential_stiffness(const PairLaw& p, double r1, double r2, double delta) {
    return 8.0 * p.gstar * std::sqrt(reduced_radius(r1, r2) * std::max(delta, 0.0));
  }
  // The integral of fn d(delta): 2/5 fn delta.
  static double energy(double fn, double delta) { return 0.4 * fn * delta; }
};

// Radius that stands for a flat wall in the pair law of a grain of radius r.
inline double wall_partner_radius(const PairLaw& p, double r) {
  return p.law == LawKind::kHertz ? HertzLaw::partner_radius(r) : LinearLaw::partner_radius(r);
}

// Normal force of the pair's law; also returns the tangential stiffness.
[[gnu::always_inline]] inline NormalResult normal_force(const PairLaw& p, double r1, double r2,
                                                        double inv_msum, double delta, double vn) {
  return p.law == LawKind::kLinear ? LinearLaw::normal(p, r1, r2, inv_msum, delta, vn)
                                   : HertzLaw::normal(p, r1, r2, inv_msum, delta, vn);
}

// The normal dashpot coefficient of a contact (the cn of normal_force), alone: what a servo
// needs to know how the force answers the speed it gives a wall.
inline double normal_dashpot(const PairLaw& p, double r1, double r2, double inv_msum,
                             double delta) {
  return p.law == LawKind::kLinear
             ? LinearLaw::dashpot(p, p.linear_kn(r1, r2), inv_msum)
             : HertzLaw::dashpot(p, std::sqrt(HertzLaw::reduced_radius(r1, r2) * delta), inv_msum);
}

// The normal stiffness dfn/ddelta of a contact whose elastic normal force is fn at overlap
// delta: what the critical time step and the servos divide by.
inline double normal_stiffness(const PairLaw& p, double r1, double r2, double fn, double delta) {
  return p.law == LawKind::kLinear ? LinearLaw::normal_stiffness(p, r1, r2)
                                   : HertzLaw::normal_stiffness(fn, delta);
}

// The energy stored in a contact's normal spring (elastic force fn > 0 at overlap delta).
inline double normal_energy(const PairLaw& p, double r1, double r2, double fn, double delta) {
  return p.law == LawKind::kLinear ? LinearLaw::energy(p, r1, r2, fn) : HertzLaw::energy(fn, delta);
}

// Keeps a spring (force or moment) in the current tangent plane with its magnitude:
// removes its normal part sn and scales by |s|/|s_t| = 1/sqrt(1 - x), x = sn^2/|s|^2.
// The normal turns little in a step, so x is tiny and the series 1 + x/2 + 3x^2/8 is
// exact to rounding (next term 5x^3/16 < 1e-16 for x < 1e-5), sparing a square root.
template <typename Vec>
[[gnu::always_inline]] inline void keep_in_tangent_plane(Vec& spring, const Vec& n) {
  const double s2 = spring.squaredNorm();
  if (s2 > 0.0) {
    const double sn = spring.dot(n);
    spring -= sn * n;
    const double x = sn * sn / s2;
    if (x < 1e-5) {
      spring *= 1.0 + x * (0.5 + 0.375 * x);
    } else if (x < 1.0) {
      spring *= 1.0 / std::sqrt(1.0 - x);
    }
  }
}

// Tangential stiffness of the pair's law at overlap delta (r2 as in normal_force).
inline double tangential_stiffness(const PairLaw& p, double r1, double r2, double delta) {
  return p.law == LawKind::kLinear ? p.linear_kt(p.linear_kn(r1, r2))
                                   : HertzLaw::tangential_stiffness(p, r1, r2, delta);
}

// Tangential velocity of body 2 against body 1 in the spring's form: the vector vrel - (vrel.n) n
// in 3D, its component along t = (-n_y, n_x) in 2D.
template <int D>
[[gnu::always_inline]] inline TangentSpring<D> tangential_velocity(const typename Dim<D>::Vec& vrel,
                                                                   const typename Dim<D>::Vec& n,
                                                                   double vn) {
  if constexpr (D == 2) {
    return n.x() * vrel.y() - n.y() * vrel.x();
  } else {
    return vrel - vn * n;
  }
}

// The spring's force as a vector (the 2D value times t).
template <int D>
[[gnu::always_inline]] inline typename Dim<D>::Vec tangential_force(const TangentSpring<D>& ft,
                                                                    const typename Dim<D>::Vec& n) {
  if constexpr (D == 2) {
    return typename Dim<D>::Vec(-ft * n.y(), ft * n.x());
  } else {
    return ft;
  }
}

// Scales a tangential force down to Coulomb's limit when it exceeds it; true if it did.
template <int D>
[[gnu::always_inline]] inline bool limit_to(TangentSpring<D>& ft, double limit) {
  if constexpr (D == 2) {
    if (std::abs(ft) <= limit) return false;
    ft = std::copysign(limit, ft);
  } else {
    const double ft2 = ft.squaredNorm();
    if (ft2 <= limit * limit) return false;
    // A frictionless contact (a lab box's smooth walls) skips the square root and division
    // (limit / |ft| is +0 then: the same bits).
    ft *= limit > 0.0 ? limit / std::sqrt(ft2) : 0.0;
  }
  return true;
}

// Updates the tangential spring (incremental, turned with the contact plane) and
// applies Coulomb's limit; returns the total force on body 2.
template <int D>
[[gnu::always_inline]] inline typename Dim<D>::Vec contact_force(
    const PairLaw& p, double r1, double r2, double inv_msum, const typename Dim<D>::Vec& n,
    double delta, const typename Dim<D>::Vec& vrel, double dt, TangentSpring<D>& spring,
    double& fn_out) {
  const double vn = vrel.dot(n);
  const NormalResult nr = normal_force(p, r1, r2, inv_msum, delta, vn);
  if constexpr (D == 3) keep_in_tangent_plane(spring, n);
  const TangentSpring<D> vt = tangential_velocity<D>(vrel, n, vn);
  spring -= (nr.kt * dt) * vt;
  const double limit = p.mu * std::max(nr.fn, 0.0);
  fn_out = nr.fn;
  if (!p.tangential_damping) {
    limit_to<D>(spring, limit);
    return nr.fn * n + tangential_force<D>(spring, n);
  }
  // Tangential dashpot with the normal coefficient (LIGGGHTS' default for Hooke):
  // when the total exceeds Coulomb's limit, the spring takes the limited total.
  TangentSpring<D> ft = spring - nr.cn * vt;
  if (limit_to<D>(ft, limit)) spring = ft;
  return nr.fn * n + tangential_force<D>(ft, n);
}

// A bonded contact (linear law): the normal spring also pulls (delta < 0 allowed) and
// the shear spring holds up to the shear strength plus friction. The bond breaks when
// the tension exceeds the tensile strength or the shear force exceeds its limit; from
// that step on the contact is frictional (`broken` is set and the force returned is
// the frictional one: zero if the grains are apart). Returns the force on body 2.
template <int D>
inline typename Dim<D>::Vec bonded_contact_force(const PairLaw& p, double r1, double r2,
                                                 double inv_msum, const typename Dim<D>::Vec& n,
                                                 double delta, const typename Dim<D>::Vec& vrel,
                                                 double dt, TangentSpring<D>& spring,
                                                 double& fn_out, bool& broken) {
  using Vec = typename Dim<D>::Vec;
  const double vn = vrel.dot(n);
  const double kn = p.linear_kn(r1, r2), kt = p.linear_kt(kn);
  const double cn =
      (p.beta > 0.0 && inv_msum > 0.0) ? 2.0 * p.beta * std::sqrt(kn / inv_msum) : 0.0;
  const double fe = kn * delta;  // elastic part: what the bond's strengths are checked against
  const double fn = fe - cn * vn;
  if constexpr (D == 3) keep_in_tangent_plane(spring, n);
  spring -= (kt * dt) * tangential_velocity<D>(vrel, n, vn);
  const double scale = p.bond_scale(r1, r2);
  const double shear_limit = p.bond_shear * scale + p.mu * std::max(fe, 0.0);
  broken = fe < -p.bond_tension * scale || spring_norm2<D>(spring) > shear_limit * shear_limit;
  if (broken && delta <= 0.0) {
    spring = unloaded_spring<D>();
    fn_out = 0.0;
    return Vec::Zero();
  }
  fn_out = fn;
  if (broken) limit_to<D>(spring, p.mu * std::max(fn, 0.0));
  return fn * n + tangential_force<D>(spring, n);
}

// Rolling (and, in 3D, twisting) resistance: elastic-plastic moment springs driven by
// the relative angular velocity wrel = w2 - w1, of stiffness kr = roll_kr kt R^2 and
// limited to eta fn R with R = PairLaw::rolling_radius (yade's CohFrictMat, LAMMPS's
// "rolling sds"). The rolling spring stays in the tangent plane. Returns the moment on
// body 2 (body 1 takes its opposite).
template <int D>
[[gnu::always_inline]] inline typename Dim<D>::Rot rolling_moment(
    const PairLaw& p, double kt, double r1, double r2, const typename Dim<D>::Vec& n,
    const typename Dim<D>::Rot& wrel, double dt, double fn, ContactExtra<D>& h) {
  const double r = PairLaw::rolling_radius(r1, r2);
  const double kr = p.roll_kr * kt * r * r;
  const double fr = std::max(fn, 0.0) * r;
  if constexpr (D == 2) {
    h.roll -= kr * dt * wrel;
    const double limit = p.roll_mu * fr;
    if (std::abs(h.roll) > limit) h.roll = std::copysign(limit, h.roll);
    return h.roll;
  } else {
    keep_in_tangent_plane(h.roll, n);
    const double wn = wrel.dot(n);
    h.roll -= (kr * dt) * (wrel - wn * n);
    const double limit = p.roll_mu * fr;
    const double m2 = h.roll.squaredNorm();
    if (m2 > limit * limit) h.roll *= limit / std::sqrt(m2);
    h.twist -= kr * dt * wn;
    const double tlimit = p.twist_mu * fr;
    if (std::abs(h.twist) > tlimit) h.twist = std::copysign(tlimit, h.twist);
    return h.roll + h.twist * n;
  }
}

}  // namespace geodem
