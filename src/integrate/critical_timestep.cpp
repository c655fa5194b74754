#include "integrate/critical_timestep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "base/parallel.hpp"
#include "contacts/contact_law.hpp"
#include "structures/spar_dynamics.hpp"
#include "structures/spar_geometry.hpp"

namespace geodem {

namespace {

// Diagonal of one body's stiffness matrix, summed over its contacts. A contact of
// normal n at lever l from the body's centre (l = r n for a round grain) adds
// kt + (kn - kt) n_a^2 to translation along axis a, and to rotation about a the diagonal
// of kn (l x n)(l x n)^T + kt sum_t (l x t)(l x t)^T, i.e. kt (|l|^2 - l_a^2) +
// (kn - kt) (l x n)_a^2 (in 2D, the one axis: kt |l|^2 + (kn - kt) (l x n)^2); a rolling
// spring adds kr to rotation about the tangent axes. Bodies are grains, then clumps.
template <int D>
struct DiagonalStiffness {
  using Vec = typename Dim<D>::Vec;
  std::vector<Vec> trans;
  std::vector<typename Dim<D>::Rot> rot;

  void reset(std::size_t n) {
    trans.assign(n, Vec::Zero());
    rot.assign(n, Dim<D>::zero_rot());
  }
  // One contact's share. kr: rolling spring (about the tangent axes); ktw: twisting spring
  // (about n, 3D).
  static SlabCrossing<D> share(std::size_t b, const Vec& n, double kn, double kt, const Vec& lever,
                               double kr, double ktw) {
    SlabCrossing<D> c;
    c.body = static_cast<std::uint32_t>(b);
    const Vec n2 = n.cwiseProduct(n);
    c.a = Vec::Constant(kt) + (kn - kt) * n2;
    const auto ln = Dim<D>::cross(lever, n);
    if constexpr (D == 2) {
      (void)ktw;
      c.b = kt * lever.squaredNorm() + (kn - kt) * ln * ln + kr;
    } else {
      c.b = kt * (Vec::Constant(lever.squaredNorm()) - lever.cwiseProduct(lever)) +
            (kn - kt) * ln.cwiseProduct(ln) + kr * (Vec::Ones() - n2) + ktw * n2;
    }
    return c;
  }
  void add(const SlabCrossing<D>& c) {
    trans[c.body] += c.a;
    rot[c.body] += c.b;
  }
  double max_trans(std::size_t i) const { return trans[i].maxCoeff(); }
  double max_rot(std::size_t i) const {
    if constexpr (D == 2) {
      return rot[i];
    } else {
      return rot[i].maxCoeff();
    }
  }
};

// The dashpots' share of the stability limit. Leapfrog with a contact dashpot of damping
// ratio z (the dashpot reads the half-step velocity) is stable for omega dt <= 2 (sqrt(1 + z^2)
// - z), not 2: for e = 0.5 (z = 0.216) that is 0.81 of the undamped limit. Without this
// factor the default safety 0.8 would leave 1 % of margin, and a deposit's grain can then
// rattle in a bounded step-to-step oscillation that never settles. z is the largest damping
// ratio of the laws that the world's grains can meet (the linear law's beta; the Hertz
// law's dashpot against its tangent stiffness, sqrt(5/6) beta = hertz_damp / 2).
template <int D>
double dashpot_factor(const World<D>& world) {
  const std::size_t nm = world.materials.size();
  static thread_local std::vector<std::uint8_t> used;  // scratch: no allocation per call
  used.assign(nm, 0);
  for (const auto m : world.particles.material) used[m] = 1;
  double z = 0.0;
  auto meet = [&z](const PairLaw& law) { z = std::max({z, law.beta, 0.5 * law.hertz_damp}); };
  for (std::size_t a = 0; a < nm; ++a) {
    if (!used[a]) continue;
    for (std::size_t b = 0; b < nm; ++b)
      if (used[b]) meet(world.pair_laws[a * nm + b]);
    for (std::size_t w = 0; w < world.walls.size(); ++w)
      meet(world.wall_laws[a * world.walls.size() + w]);
    for (const auto sm : world.spars.material) meet(world.pair_laws[a * nm + sm]);
  }
  return std::sqrt(1.0 + z * z) - z;
}

}  // namespace

template <int D>
double critical_timestep(const World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = world.particles;
  const auto& L = world.nlist;
  const std::size_t n = P.size();
  // Scratch of the calling thread, reached by reference inside the parallel region.
  static thread_local DiagonalStiffness<D> stiffness;
  DiagonalStiffness<D>& K = stiffness;
  const auto& C = world.clumps;
  K.reset(n + C.size());
  // The body a grain's contacts load, and the lever from its centre to a contact point.
  const bool clumps = !P.clump.empty();
  auto body = [&](std::size_t i) { return clumps && P.clump[i] != kNoClump ? n + P.clump[i] : i; };
  auto lever = [&](std::size_t i, const Vec& to_contact) -> Vec {
    const Vec l = P.radius[i] * to_contact;
    return clumps && P.clump[i] != kNoClump ? Vec(P.pos[i] + l - C.pos[P.clump[i]]) : l;
  };

  const bool have_list = L.start.size() == n + 1;
  const bool extras = L.extra.size() == L.other.size() && !L.extra.empty();
  // Slabs side by side, as in the force stage (contacts/contact_forces.cpp): a share for a
  // body outside the slab (a grain of a later slab, a clump) is added afterwards, in slab
  // order, so that the sums, and dt, do not depend on the thread count.
  auto& crossing = world.slab_crossing;
  const SlabPlan plan = have_list ? world.slab_plan(n) : SlabPlan::uniform(0);
  crossing.prepare(plan, world.threads);
  for_slabs(plan, world.threads, [&](std::size_t s, std::size_t first, std::size_t last) {
    auto out = crossing.slab(s);
    auto add = [&](std::size_t b, const Vec& nrm, double kn, double kt, const Vec& l, double kr,
                   double ktw) {
      const SlabCrossing<D> c = DiagonalStiffness<D>::share(b, nrm, kn, kt, l, kr, ktw);
      if (b >= first && b < last) {
        K.add(c);
      } else {
        out.push(c);
      }
    };
    for (std::size_t i = first; i < last; ++i) {
      for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
        const std::uint32_t j = L.other[k];
        const double rs = P.radius[i] + P.radius[j];
        const Vec d = world.branch(i, j, k);
        // A bonded pair pulled apart still has its springs.
        const bool bonded = extras && L.extra[k].bonded;
        // Most listed pairs are apart: leave them before the square root (the margin keeps
        // the exact test below the judge of pairs at the contact distance).
        const double d2 = d.squaredNorm();
        if (!bonded && d2 > rs * rs * (1.0 + 1e-9)) continue;
        const double dist = std::sqrt(d2);
        if ((dist >= rs && !bonded) || dist <= 0.0) continue;
        const PairLaw& law = world.pair_law(P.material[i], P.material[j]);
        const double delta = rs - dist;
        const NormalResult nr = normal_force(law, P.radius[i], P.radius[j], 0.0, delta, 0.0);
        const double kn = normal_stiffness(law, P.radius[i], P.radius[j], nr.fn, delta);
        const Vec nrm = d / dist;
        const double k_roll = law.rolling_stiffness(nr.kt, P.radius[i], P.radius[j]);
        const double kr = law.roll_mu > 0.0 ? k_roll : 0.0, ktw = law.twist_mu > 0.0 ? k_roll : 0.0;
        add(body(i), nrm, kn, nr.kt, lever(i, nrm), kr, ktw);
        add(body(j), nrm, kn, nr.kt, lever(j, -nrm), kr, ktw);
      }
      for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
        Vec nrm;
        double delta;
        if (!wall_overlap(world.walls[L.wall[k]], P.pos[i], P.radius[i], nrm, delta)) continue;
        const PairLaw& law = world.wall_law(P.material[i], L.wall[k]);
        const double r2 = wall_partner_radius(law, P.radius[i]);
        const NormalResult nr = normal_force(law, P.radius[i], r2, 0.0, delta, 0.0);
        const double kn = normal_stiffness(law, P.radius[i], r2, nr.fn, delta);
        const double k_roll = law.rolling_stiffness(nr.kt, P.radius[i], kWallRadius);
        const double kr = law.roll_mu > 0.0 ? k_roll : 0.0, ktw = law.twist_mu > 0.0 ? k_roll : 0.0;
        add(body(i), nrm, kn, nr.kt, lever(i, nrm), kr, ktw);
      }
      if (L.spar_start.size() != n + 1) continue;
      const auto& S = world.spars;
      for (std::uint32_t k = L.spar_start[i]; k < L.spar_start[i + 1]; ++k) {
        const std::size_t e = L.spar[k];
        const SparPoint<D> p = spar_point(S, e, P.pos[i]);
        const Vec d = p.closest - P.pos[i];
        const double dist = d.norm();
        if (p.region != SparRegion::kOwned || dist <= 0.0 ||
            dist >= P.radius[i] + S.half_thickness[e])
          continue;
        const PairLaw& law = world.pair_law(P.material[i], S.material[e]);
        const double delta = P.radius[i] + S.half_thickness[e] - dist;
        const double r2 = wall_partner_radius(law, P.radius[i]);
        const NormalResult nr = normal_force(law, P.radius[i], r2, 0.0, delta, 0.0);
        const double kn = normal_stiffness(law, P.radius[i], r2, nr.fn, delta);
        const Vec nrm = d / dist;
        add(body(i), nrm, kn, nr.kt, lever(i, nrm), 0.0, 0.0);
      }
    }
  });
  crossing.apply(world.threads, [&K](const SlabCrossing<D>& c) { K.add(c); });

  // dt^2 = 2 x the smallest of m/K_t and I/K_r (the sqrt(2) of yade: the critical
  // step of a grain on a spring whose other end moves in antiphase).
  // (a minimum over grains: the same in any order)
  const double inf = std::numeric_limits<double>::infinity();
  auto grain_dt2 = [&](std::ptrdiff_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    // A ghost's contacts are its owner's to count (here it lacks those with other ghosts).
    if (P.inv_mass[i] == 0.0 || (P.flags[i] & kGhost)) return inf;
    const double m = 1.0 / P.inv_mass[i], inertia = 1.0 / P.inv_inertia[i];
    const auto& mat = world.materials[P.material[i]];
    const PairLaw& self = world.pair_law(P.material[i], P.material[i]);
    // A grain without contacts yet: its first collision with an equal grain (linear
    // law), or 0.2 x the Rayleigh wave time (Hertz law).
    double d = inf;
    if (self.law == LawKind::kLinear) {
      const double kn = self.linear_kn(P.radius[i], P.radius[i]);
      d = std::min(d, m / std::max(kn, self.linear_kt(kn)));
    } else {
      const double shear = mat.young / (2.0 * (1.0 + mat.poisson));
      const double rayleigh = 0.2 * std::numbers::pi * P.radius[i] *
                              std::sqrt(mat.density / shear) / (0.1631 * mat.poisson + 0.8766);
      d = std::min(d, 0.5 * rayleigh * rayleigh);
    }
    if (P.member(i)) return d;  // its clump's stiffness is checked below
    const double kt = K.max_trans(i), kr = K.max_rot(i);
    if (kt > 0.0) d = std::min(d, m / kt);
    if (kr > 0.0) d = std::min(d, inertia / kr);
    return d;
  };
  double dt2 = extreme_over_indices<false>(static_cast<std::ptrdiff_t>(n), world.threads,
                                           n >= kParallelMin, inf, grain_dt2);
  for (std::size_t c = 0; c < C.owned(); ++c) {  // (a ghost clump is its owner's to check)
    const double kt = K.max_trans(n + c), kr = K.max_rot(n + c);
    if (kt > 0.0) dt2 = std::min(dt2, 1.0 / (C.inv_mass[c] * kt));
    if (kr > 0.0) dt2 = std::min(dt2, Clumps<D>::min_moment(C.inertia[c]) / kr);
  }
  dt2 = std::min(dt2, spar_min_mass_over_stiffness(world));
  return world.dt_safety * dashpot_factor(world) * std::sqrt(2.0 * dt2);
}

template double critical_timestep<2>(const World<2>&);
template double critical_timestep<3>(const World<3>&);

}  // namespace geodem
