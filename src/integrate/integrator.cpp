#include "integrate/integrator.hpp"

#include <algorithm>
#include <cmath>

#include "base/parallel.hpp"
#include "clumps/clump_dynamics.hpp"
#include "contacts/contact_batch.hpp"
#include "integrate/move_kernel.hpp"
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

// The grains' arrays as one step's move reads and writes them. Raw pointers: the compiler then
// knows the arrays do not move inside the loop.
template <int D>
struct GrainArrays {
  typename Dim<D>::Vec* __restrict pos;
  typename Dim<D>::Vec* __restrict vel;
  typename Dim<D>::Rot* __restrict angvel;
  const typename Dim<D>::Vec* __restrict force;
  const typename Dim<D>::Rot* __restrict torque;
  const double* __restrict inv_mass;
  const double* __restrict inv_inertia;
  const std::uint8_t* __restrict flags;
  typename Dim<D>::Orient* __restrict orient;
};

// Moves the grains from `first` on by one step; returns the largest speed squared (exact in any
// order). The options are template parameters so that the loop over the grains carries no test
// of them.
template <int D, bool Damped, bool Periodic, bool Track>
double move_grains(const World<D>& world, const GrainArrays<D>& A, std::size_t first) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  const std::size_t n = world.particles.size();
  const double dt = world.dt, alpha = world.local_damping;
  const Vec g = world.gravity;
  // In a periodic cell, velocities are relative to the cell's affine field L x.
  const typename Dim<D>::Tensor L = world.cell.vel_grad;
  auto move = [&A, dt, alpha, g, &L](std::ptrdiff_t i) [[gnu::always_inline]] {
    // Moved with its clump below, or a ghost (its owner moves it).
    if (A.flags[i] & (kClumpMember | kGhost)) return 0.0;
    if (!(A.flags[i] & kFixed)) {
      Vec a = A.force[i] * A.inv_mass[i] + g;
      Rot aw = A.torque[i] * A.inv_inertia[i];
      if constexpr (Damped) {
        damp(a, A.vel[i], alpha, dt);
        damp(aw, A.angvel[i], alpha, dt);
      }
      A.vel[i] += a * dt;
      A.angvel[i] += aw * dt;
    }
    if constexpr (Periodic) {
      A.pos[i] += (A.vel[i] + L * A.pos[i]) * dt;
    } else {
      A.pos[i] += A.vel[i] * dt;
    }
    if constexpr (Track) Dim<D>::rotate(A.orient[i], A.angvel[i], dt);
    return A.vel[i].squaredNorm();
  };
  return extreme_over_indices<true>(
      static_cast<std::ptrdiff_t>(n - first), world.threads, n - first >= kParallelMin, 0.0,
      [&](std::ptrdiff_t i) { return move(static_cast<std::ptrdiff_t>(first) + i); });
}

template <int D, bool Damped, bool Periodic>
double move_grains(const World<D>& world, const GrainArrays<D>& A, std::size_t first) {
  return world.track_orientation ? move_grains<D, Damped, Periodic, true>(world, A, first)
                                 : move_grains<D, Damped, Periodic, false>(world, A, first);
}

template <int D, bool Damped>
double move_grains(const World<D>& world, const GrainArrays<D>& A, std::size_t first) {
  return world.cell.periodic ? move_grains<D, Damped, true>(world, A, first)
                             : move_grains<D, Damped, false>(world, A, first);
}

// The whole blocks of grains by the move kernel of the step's instruction set
// (integrate/move_kernel.hpp) where it applies; returns how many grains it moved (the rest
// go through the scalar loop) and the largest speed squared among them.
template <int D>
std::size_t move_blocks(const World<D>& world, const GrainArrays<D>& A, double& vmax2) {
  vmax2 = 0.0;
#if defined(__x86_64__) && defined(__GNUC__)
  const ContactPath path = contact_path();
  if (world.cell.periodic || world.track_orientation ||
      (path != ContactPath::kAvx2 && path != ContactPath::kAvx512))
    return 0;
  MoveConstants c;
  c.dt = world.dt;
  c.alpha = world.local_damping;
  for (int k = 0; k < D; ++k) c.gravity[k] = world.gravity[k];
  c.left_alone = kClumpMember | kGhost;
  c.fixed = kFixed;
  const MoveArrays m{
      as_doubles(A.pos),    as_doubles(A.vel), as_doubles(A.angvel), as_doubles(A.force),
      as_doubles(A.torque), A.inv_mass,        A.inv_inertia,        A.flags};
  const std::size_t n = world.particles.size(), whole = n - n % kMoveBlock;
  // The whole blocks by the force stage's slabs, in its fixed shares per thread
  // (base/slab_shares.hpp): a thread then moves mostly the grains whose forces it has just
  // added up, still in its core's cache. (Chunks in static halves moved the other thread's
  // slabs as often as not: on two threads of a 2-vCPU VM one half took twice the other's
  // time.) A block goes with the slab of its first grain. One term of the maximum per slab.
  const SlabPlan plan = world.slab_plan(n);
  static thread_local std::vector<double> slab_vmax2;
  slab_vmax2.assign(plan.count, 0.0);
  double* part = slab_vmax2.data();  // (in the region, the thread-local's name is per thread)
  auto block_start = [whole](std::size_t i) {
    return std::min(whole, (i + kMoveBlock - 1) / kMoveBlock * kMoveBlock);
  };
  for_slabs(plan, world.threads, [&](std::size_t s, std::size_t first, std::size_t last) {
    const std::size_t b = block_start(first), e = block_start(last);
    if (b >= e) return;
    part[s] = path == ContactPath::kAvx512 ? move_kernel_avx512<D>(c, m, b, e)
                                           : move_kernel_avx2<D>(c, m, b, e);
  });
  for (std::size_t s = 0; s < plan.count; ++s) vmax2 = std::max(vmax2, part[s]);
  return whole;
#else
  (void)world, (void)A;
  return 0;
#endif
}

}  // namespace

template <int D>
void integrate(World<D>& world) {
  auto& P = world.particles;
  const std::size_t n = P.size();
  const double dt = world.dt;
  if (world.track_orientation && P.orient.size() != n) P.orient.resize(n, Dim<D>::identity());
  const GrainArrays<D> arrays{P.pos.data(),         P.vel.data(),    P.angvel.data(),
                              P.force.data(),       P.torque.data(), P.inv_mass.data(),
                              P.inv_inertia.data(), P.flags.data(),  P.orient.data()};
  const bool periodic = world.cell.periodic;
  const typename Dim<D>::Tensor L = world.cell.vel_grad;
  double vmax2 = 0.0;
  const std::size_t first = move_blocks(world, arrays, vmax2);
  vmax2 = std::max(vmax2, world.local_damping > 0.0 ? move_grains<D, true>(world, arrays, first)
                                                    : move_grains<D, false>(world, arrays, first));
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
