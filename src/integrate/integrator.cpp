#include "integrate/integrator.hpp"

#include <algorithm>
#include <cmath>

#include "base/parallel.hpp"
#include "clumps/clump_dynamics.hpp"
#include "structures/spar_dynamics.hpp"

namespace geodem {

namespace {

// Applies local damping to an acceleration given the half-step velocity:
// a <- a - alpha |a| sign(v), with the on-step velocity v = v_half + a dt/2.
// copysign keeps it free of branches, which the random signs would mispredict.
inline void damp(double& a, double v_half, double alpha, double dt) {
  a -= std::copysign(alpha * std::abs(a), v_half + 0.5 * dt * a);
}
template <typename V>
inline void damp(V& a, const V& v_half, double alpha, double dt) {
  for (int k = 0; k < a.size(); ++k) damp(a[k], v_half[k], alpha, dt);
}

}  // namespace

template <int D>
void integrate(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  auto& P = world.particles;
  const std::size_t n = P.size();
  const double dt = world.dt, alpha = world.local_damping;
  const Vec g = world.gravity;
  // Raw pointers: the compiler then knows the arrays do not move inside the loop.
  Vec* __restrict pos = P.pos.data();
  Vec* __restrict vel = P.vel.data();
  Rot* __restrict angvel = P.angvel.data();
  const Vec* __restrict force = P.force.data();
  const Rot* __restrict torque = P.torque.data();
  const double* __restrict inv_mass = P.inv_mass.data();
  const double* __restrict inv_inertia = P.inv_inertia.data();
  const std::uint8_t* __restrict flags = P.flags.data();
  if (world.track_orientation && P.orient.size() != n) P.orient.resize(n, Dim<D>::identity());
  auto* __restrict orient = P.orient.data();
  const bool track = world.track_orientation;
  // In a periodic cell, velocities are relative to the cell's affine field L x.
  const bool periodic = world.cell.periodic;
  const typename Dim<D>::Tensor L = world.cell.vel_grad;
  // Moves grain i; returns its speed squared (a maximum over grains: the same in any order).
  auto move = [&](std::ptrdiff_t i) {
    // Moved with its clump below, or a ghost (its owner moves it).
    if (flags[i] & (kClumpMember | kGhost)) return 0.0;
    if (!(flags[i] & kFixed)) {
      Vec a = force[i] * inv_mass[i] + g;
      Rot aw = torque[i] * inv_inertia[i];
      if (alpha > 0.0) {
        damp(a, vel[i], alpha, dt);
        damp(aw, angvel[i], alpha, dt);
      }
      vel[i] += a * dt;
      angvel[i] += aw * dt;
    }
    if (periodic) {
      pos[i] += (vel[i] + L * pos[i]) * dt;
    } else {
      pos[i] += vel[i] * dt;
    }
    if (track) Dim<D>::rotate(orient[i], angvel[i], dt);
    return vel[i].squaredNorm();
  };
  double vmax2 = extreme_over_indices<true>(static_cast<std::ptrdiff_t>(n), world.threads,
                                            n >= kParallelMin, 0.0, move);
  vmax2 = std::max(vmax2, integrate_clumps(world));
  // Bound on how far any grain moved since the neighbour list was checked (spar nodes
  // are checked exactly, like walls: they are few).
  // In a periodic cell the displacement from the affine motion, u, grows at v + L u.
  if (periodic) world.disp_bound += L.norm() * world.disp_bound * dt;
  if (world.domain)
    world.last_move = std::sqrt(vmax2) * dt;  // (taken over ranks at the next list check)
  else
    world.disp_bound += std::sqrt(vmax2) * dt;
  if (!world.spars.empty()) integrate_spar_nodes(world);
}

template <int D>
void move_walls(World<D>& world) {
  for (auto& w : world.walls) {
    const auto d = w.velocity * world.dt;
    w.point += d;
    w.end += d;
    w.displacement += d;
  }
}

template void integrate<2>(World<2>&);
template void integrate<3>(World<3>&);
template void move_walls<2>(World<2>&);
template void move_walls<3>(World<3>&);

}  // namespace geodem
