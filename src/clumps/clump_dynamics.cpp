#include "clumps/clump_dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "base/exact_sum.hpp"
#include "base/parallel.hpp"

namespace geodem {

namespace {

// Cundall's local damping of one component (see integrate/integrator.cpp).
inline double damped(double a, double v, double alpha) {
  return a - std::copysign(alpha * std::abs(a), v);
}

// Rotation of the body by angle `phi` about its own principal axis K: the orientation
// composes on the right, and the body-frame angular momentum turns the other way.
// The angles are tiny in DEM (|omega| dt ~ 1e-4): below 1e-3 rad the half-angle cosine
// and sine come from their Taylor series (the first term left out is below 1e-21), the
// full angle's from the double-angle formulas, sparing the library calls that would
// dominate the cost.
template <int K>
inline void rotate_about_body_axis(Eigen::Quaterniond& q, Eigen::Vector3d& lb, double phi) {
  constexpr int a = (K + 1) % 3, b = (K + 2) % 3;
  const double h = 0.5 * phi;
  double c, s;
  if (std::abs(h) < 1e-3) {
    const double h2 = h * h;
    c = 1.0 - h2 * (0.5 - h2 * (1.0 / 24.0));
    s = h * (1.0 - h2 * ((1.0 / 6.0) - h2 * (1.0 / 120.0)));
  } else {
    c = std::cos(h);
    s = std::sin(h);
  }
  // q <- q (c + s e_K): with p = q's vector part and w its scalar part,
  // w' = c w - s p_K, p' = c p + s (w e_K + p x e_K). Scalar code: the components are
  // mixed across lanes, which packed arithmetic would only shuffle.
  double* qc = q.coeffs().data();  // x, y, z, w
  const double w = qc[3], pk = qc[K], pa = qc[a], pb = qc[b];
  qc[3] = c * w - s * pk;
  qc[K] = c * pk + s * w;
  qc[a] = c * pa + s * pb;  // (p x e_K)_a = p_b
  qc[b] = c * pb - s * pa;  // (p x e_K)_b = -p_a
  const double cp = 1.0 - 2.0 * s * s, sp = 2.0 * s * c;
  const double la = lb[a], lbb = lb[b];
  lb[a] = cp * la + sp * lbb;
  lb[b] = -sp * la + cp * lbb;
}

// Free rotation of a rigid body over dt at constant world angular momentum: the
// symmetric splitting of Dullweber, Leimkuhler & McLachlan (1997) into exact rotations
// about the principal axes (1/2, 2/2, 3, 2/2, 1/2). It is symplectic and keeps the
// world angular momentum exactly; the energy error stays bounded, of order (omega dt)^2.
// `lb` enters as the body-frame angular momentum and leaves updated with `q`.
inline void free_rotation(Eigen::Quaterniond& q, Eigen::Vector3d& lb,
                          const Eigen::Vector3d& inv_inertia, double dt) {
  const double h = 0.5 * dt;
  rotate_about_body_axis<0>(q, lb, h * lb[0] * inv_inertia[0]);
  rotate_about_body_axis<1>(q, lb, h * lb[1] * inv_inertia[1]);
  rotate_about_body_axis<2>(q, lb, dt * lb[2] * inv_inertia[2]);
  rotate_about_body_axis<1>(q, lb, h * lb[1] * inv_inertia[1]);
  rotate_about_body_axis<0>(q, lb, h * lb[0] * inv_inertia[0]);
  q.coeffs() *= 1.5 - 0.5 * q.squaredNorm();  // one Newton step back to |q| = 1
}

// The same for two bodies at once, interleaved (independent chains overlap in the CPU).
inline void free_rotation_pair(Eigen::Quaterniond& q0, Eigen::Vector3d& lb0,
                               const Eigen::Vector3d& ii0, Eigen::Quaterniond& q1,
                               Eigen::Vector3d& lb1, const Eigen::Vector3d& ii1, double dt) {
  const double h = 0.5 * dt;
  rotate_about_body_axis<0>(q0, lb0, h * lb0[0] * ii0[0]);
  rotate_about_body_axis<0>(q1, lb1, h * lb1[0] * ii1[0]);
  rotate_about_body_axis<1>(q0, lb0, h * lb0[1] * ii0[1]);
  rotate_about_body_axis<1>(q1, lb1, h * lb1[1] * ii1[1]);
  rotate_about_body_axis<2>(q0, lb0, dt * lb0[2] * ii0[2]);
  rotate_about_body_axis<2>(q1, lb1, dt * lb1[2] * ii1[2]);
  rotate_about_body_axis<1>(q0, lb0, h * lb0[1] * ii0[1]);
  rotate_about_body_axis<1>(q1, lb1, h * lb1[1] * ii1[1]);
  rotate_about_body_axis<0>(q0, lb0, h * lb0[0] * ii0[0]);
  rotate_about_body_axis<0>(q1, lb1, h * lb1[0] * ii1[0]);
  q0.coeffs() *= 1.5 - 0.5 * q0.squaredNorm();
  q1.coeffs() *= 1.5 - 0.5 * q1.squaredNorm();
}

}  // namespace

template <int D>
void sort_clumps_by_members(World<D>& world) {
  auto& P = world.particles;
  auto& C = world.clumps;
  if (C.size() == 0) return;
  static thread_local std::vector<std::uint32_t> order, new_index;
  order.clear();
  new_index.assign(C.size(), kNoClump);
  for (std::size_t i = 0; i < P.size(); ++i) {
    const std::uint32_t c = P.clump[i];
    if (c == kNoClump || new_index[c] != kNoClump) continue;
    new_index[c] = static_cast<std::uint32_t>(order.size());
    order.push_back(c);
  }
  for (std::size_t c = 0; c < C.size(); ++c)  // clumps without members (none in practice)
    if (new_index[c] == kNoClump) {
      new_index[c] = static_cast<std::uint32_t>(order.size());
      order.push_back(static_cast<std::uint32_t>(c));
    }
  C.permute(order);
  for (auto& c : P.clump)
    if (c != kNoClump) c = new_index[c];
}

template <int D>
double place_members(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  using Mat = Eigen::Matrix<double, D, D>;
  auto& P = world.particles;
  const auto& C = world.clumps;
  if (C.size() == 0) return 0.0;
  const Mat* __restrict R = C.rotation.data();
  const auto n = static_cast<std::ptrdiff_t>(P.size());
  const std::size_t owned = C.owned();
  // (a maximum of the members' speeds: the same in any order)
  return extreme_over_indices<true>(
      n, world.threads, P.size() >= kParallelMin, 0.0, [&](std::ptrdiff_t k) {
        const auto i = static_cast<std::size_t>(k);
        const std::uint32_t c = P.clump[i];
        if (c >= owned) return 0.0;  // no clump, or a ghost clump (its owner places the members)
        const Vec arm = R[c] * P.body_offset[i];
        P.pos[i] = C.pos[c] + arm;
        P.vel[i] = C.vel[c] + Dim<D>::cross(C.angvel[c], arm);
        P.angvel[i] = C.angvel[c];
        return P.vel[i].squaredNorm();
      });
}

namespace {

// Each clump's members in ascending grain order (compressed rows), remade when grains may
// have been renumbered since.
template <int D>
const typename StepScratch<D>::ClumpMembers& clump_members(World<D>& world) {
  auto& m = world.clump_members;
  const auto& P = world.particles;
  const std::size_t nc = world.clumps.size();
  if (m.builds == world.nlist.builds && m.grains == P.size() && m.clumps == nc) return m;
  m.start.assign(nc + 1, 0);
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.clump[i] != kNoClump) ++m.start[P.clump[i] + 1];
  for (std::size_t c = 0; c < nc; ++c) m.start[c + 1] += m.start[c];
  m.grain.resize(m.start[nc]);
  std::vector<std::uint32_t> fill(m.start.begin(), m.start.end() - 1);
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.clump[i] != kNoClump) m.grain[fill[P.clump[i]]++] = static_cast<std::uint32_t>(i);
  m.builds = world.nlist.builds;
  m.grains = P.size();
  m.clumps = nc;
  return m;
}

}  // namespace

// Every loop runs clump by clump (or grain by grain), each writing only its own clump or
// grain; a clump's members are summed in grain order. The results do not depend on the
// number of threads.
// A decomposed world's fabric correction (the one process's is in integrate_clumps): each
// rank's own members, summed exactly, added over ranks. Every rank calls it on a measuring
// step, with clumps or without (a collective).
template <int D>
void correct_fabric_over_ranks(World<D>& world) {
  const auto& P = world.particles;
  const auto& C = world.clumps;
  std::vector<ExactSum> sums(D * D);
  for (std::size_t i = 0; i < P.clump.size(); ++i) {
    const std::uint32_t c = P.clump[i];
    if (c >= C.owned()) continue;  // no clump, or a ghost clump's member
    const typename Dim<D>::Vec arm = C.pos[c] - P.pos[i];
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b)
        sums[static_cast<std::size_t>(a * D + b)].add(arm[a] * P.force[i][b]);
  }
  world.domain->sum(sums);
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      world.stats.fabric_stress(a, b) += sums[static_cast<std::size_t>(a * D + b)].value();
}

template <int D>
double integrate_clumps(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  auto& P = world.particles;
  auto& C = world.clumps;
  if (world.domain && world.measure_this_step) correct_fabric_over_ranks(world);
  const std::size_t nc = C.owned();  // (a decomposed world's ghost clumps are not integrated)
  if (nc == 0) return 0.0;
  const bool par = world.threads > 1 && nc >= kParallelMin / 2;
  const auto ncs = static_cast<std::ptrdiff_t>(nc);
  // Resultants about each centre of mass.
  const auto& members = clump_members(world);
  const std::uint32_t* mstart = members.start.data();
  const std::uint32_t* mgrain = members.grain.data();
  for_each_index(ncs, world.threads, par, [&](std::ptrdiff_t k) {
    const auto c = static_cast<std::size_t>(k);
    Vec f = Vec::Zero();
    typename Dim<D>::Rot t = Dim<D>::zero_rot();
    for (std::uint32_t m = mstart[c]; m < mstart[c + 1]; ++m) {
      const std::uint32_t i = mgrain[m];
      const Vec arm = P.pos[i] - C.pos[c];
      f += P.force[i];
      t += P.torque[i] + Dim<D>::cross(arm, P.force[i]);
    }
    C.force[c] = f;
    C.torque[c] = t;
  });
  // When the contact stage measured the fabric stress with member centres as the grains'
  // centres, the clump's own centre replaces them: add (X - x_m) (x) F_m for each member m
  // (docs/physics.md, "Clumps"); one sum, in grain order. (A decomposed world: above.)
  if (world.measure_this_step && !world.domain) {
    auto& fabric = world.stats.fabric_stress;
    for (std::size_t i = 0; i < P.size(); ++i) {
      const std::uint32_t c = P.clump[i];
      if (c != kNoClump) fabric -= (P.pos[i] - C.pos[c]) * P.force[i].transpose();
    }
  }
  const double dt = world.dt, alpha = world.local_damping;
  const Vec g = world.gravity;
  static thread_local std::vector<Vec> body_momentum;  // 3D: angular momentum, body frame
  if constexpr (D == 3) body_momentum.resize(nc);
  Vec* lb = body_momentum.data();
  const bool any_held = !C.held.empty();
  for_each_index(ncs, world.threads, par, [&](std::ptrdiff_t k) {
    const auto c = static_cast<std::size_t>(k);
    if (any_held && C.held[c]) {  // kept still: no kick, no drift, no turn
      C.vel[c].setZero();
      C.angvel[c] = Dim<D>::zero_rot();
      if constexpr (D == 3) {
        C.angmom[c].setZero();
        lb[c].setZero();
      }
      return;
    }
    Vec a = C.force[c] * C.inv_mass[c] + g;
    if (alpha > 0.0)
      for (int d = 0; d < D; ++d) a[d] = damped(a[d], C.vel[c][d] + 0.5 * dt * a[d], alpha);
    C.vel[c] += a * dt;
    if (world.cell.periodic) {  // the affine field of the periodic cell carries the centre
      C.pos[c] += (C.vel[c] + world.cell.vel_grad * C.pos[c]) * dt;
    } else {
      C.pos[c] += C.vel[c] * dt;
    }
    if constexpr (D == 2) {
      double aw = C.torque[c] * C.inv_inertia[c];
      if (alpha > 0.0) aw = damped(aw, C.angvel[c] + 0.5 * dt * aw, alpha);
      C.angvel[c] += aw * dt;
      const double turn = C.angvel[c] * dt;
      C.orient[c] += turn;
      // Compose the rotation matrix with the step's small turn (Taylor series of cos and
      // sin, exact to rounding below 1e-2 rad; one Newton step keeps c^2 + s^2 = 1).
      auto& R = C.rotation[c];
      if (std::abs(turn) < 1e-2) {
        const double t2 = turn * turn;
        const double co = 1.0 - t2 * (0.5 - t2 * ((1.0 / 24.0) - t2 * (1.0 / 720.0)));
        const double si =
            turn * (1.0 - t2 * ((1.0 / 6.0) - t2 * ((1.0 / 120.0) - t2 * (1.0 / 5040.0))));
        double c0 = R(0, 0), s0 = R(1, 0);
        const double c1 = c0 * co - s0 * si, s1 = s0 * co + c0 * si;
        const double fix = 1.5 - 0.5 * (c1 * c1 + s1 * s1);
        c0 = c1 * fix, s0 = s1 * fix;
        R << c0, -s0, s0, c0;
      } else {
        R = Clumps<D>::matrix(C.orient[c]);
      }
    } else {
      // Kick: world angular momentum; then its body-frame value for the free rotation.
      Vec t = C.torque[c];
      if (alpha > 0.0)
        for (int d = 0; d < 3; ++d) t[d] = damped(t[d], C.angvel[c][d], alpha);
      C.angmom[c] += t * dt;
      lb[c] = C.rotation[c].transpose() * C.angmom[c];
    }
  });
  if constexpr (D == 3) {
    // Free rotations two clumps at a time: each is a long chain of dependent operations,
    // and two independent chains side by side let the processor overlap them.
    const auto pairs = static_cast<std::ptrdiff_t>(nc / 2);
    for_each_index(pairs, world.threads, par, [&](std::ptrdiff_t k) {
      const auto c = 2 * static_cast<std::size_t>(k);
      free_rotation_pair(C.orient[c], lb[c], C.inv_inertia[c], C.orient[c + 1], lb[c + 1],
                         C.inv_inertia[c + 1], dt);
    });
    if (nc % 2 == 1) free_rotation(C.orient[nc - 1], lb[nc - 1], C.inv_inertia[nc - 1], dt);
    for_each_index(ncs, world.threads, par, [&](std::ptrdiff_t k) {
      const auto c = static_cast<std::size_t>(k);
      C.rotation[c] = C.orient[c].toRotationMatrix();
      C.angvel[c] = C.rotation[c] * Vec(lb[c].cwiseProduct(C.inv_inertia[c]));
    });
  }
  return place_members(world);
}

template <int D>
std::size_t add_clump(World<D>& world, const ResolvedClump<D>& t, const typename Dim<D>::Vec& x,
                      const typename Dim<D>::Orient& q, double scale, double density,
                      std::uint16_t material, const typename Dim<D>::Vec& v) {
  using Vec = typename Dim<D>::Vec;
  auto& P = world.particles;
  auto& C = world.clumps;
  const double mass = density * t.volume * std::pow(scale, D);
  const typename Dim<D>::Rot inertia = density * std::pow(scale, D + 2) * t.principal;
  const std::size_t c = C.size();
  C.pos.push_back(x);
  C.vel.push_back(v);
  C.angvel.push_back(Dim<D>::zero_rot());
  C.angmom.push_back(Dim<D>::zero_rot());
  C.orient.push_back(q);
  C.rotation.push_back(Clumps<D>::matrix(q));
  C.force.push_back(Vec::Zero());
  C.torque.push_back(Dim<D>::zero_rot());
  C.inv_mass.push_back(1.0 / mass);
  C.inertia.push_back(inertia);
  if constexpr (D == 2)
    C.inv_inertia.push_back(1.0 / inertia);
  else
    C.inv_inertia.push_back(inertia.cwiseInverse());
  C.volume.push_back(t.volume * std::pow(scale, D));
  C.id.push_back(C.next_id++);
  if (!C.held.empty()) C.held.push_back(0);
  for (std::size_t m = 0; m < t.offset.size(); ++m) {
    const Vec off = scale * t.offset[m];
    const std::size_t i =
        P.add(x + Clumps<D>::matrix(q) * off, scale * t.radius[m], density, material, v);
    // The first member ever switches the membership arrays on for every grain.
    P.clump.resize(P.size(), kNoClump);
    P.body_offset.resize(P.size(), Vec::Zero());
    // Contact laws that need a mass (viscous damping) and the first time-step estimate
    // see the clump's.
    P.inv_mass[i] = 1.0 / mass;
    P.inv_inertia[i] = 1.0 / Clumps<D>::min_moment(inertia);
    P.flags[i] |= kClumpMember;
    P.clump[i] = static_cast<std::uint32_t>(c);
    P.body_offset[i] = off;
  }
  world.rebuild_needed = true;
  return c;
}

template <>
Dim<2>::Orient random_orientation<2>(double u1, double, double) {
  return 2.0 * std::numbers::pi * u1;
}
// Shoemake's uniform random unit quaternion from three uniform numbers in [0, 1).
template <>
Dim<3>::Orient random_orientation<3>(double u1, double u2, double u3) {
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1), t1 = 2.0 * std::numbers::pi * u2,
               t2 = 2.0 * std::numbers::pi * u3;
  return Eigen::Quaterniond(b * std::cos(t2), a * std::sin(t1), a * std::cos(t1), b * std::sin(t2));
}

template double integrate_clumps<2>(World<2>&);
template double integrate_clumps<3>(World<3>&);
template void sort_clumps_by_members<2>(World<2>&);
template void sort_clumps_by_members<3>(World<3>&);
template double place_members<2>(World<2>&);
template double place_members<3>(World<3>&);
template std::size_t add_clump<2>(World<2>&, const ResolvedClump<2>&, const Dim<2>::Vec&,
                                  const Dim<2>::Orient&, double, double, std::uint16_t,
                                  const Dim<2>::Vec&);
template std::size_t add_clump<3>(World<3>&, const ResolvedClump<3>&, const Dim<3>::Vec&,
                                  const Dim<3>::Orient&, double, double, std::uint16_t,
                                  const Dim<3>::Vec&);

}  // namespace geodem
