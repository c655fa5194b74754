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
double move_grains(const World<D>& world, const GrainArrays<D>& A, std::size_t first,
                   std::size_t last, bool parallel) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
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
      static_cast<std::ptrdiff_t>(last - first), world.threads, parallel, 0.0,
      [&](std::ptrdiff_t i) { return move(static_cast<std::ptrdiff_t>(first) + i); });
}

// The grains [first, last) by the scalar loop, on threads where `parallel`; returns the
// largest speed squared.
template <int D>
double move_grains(const World<D>& world, const GrainArrays<D>& A, std::size_t first,
                   std::size_t last, bool parallel) {
  auto with = [&]<bool Damped, bool Periodic>() {
    return world.track_orientation
               ? move_grains<D, Damped, Periodic, true>(world, A, first, last, parallel)
               : move_grains<D, Damped, Periodic, false>(world, A, first, last, parallel);
  };
  const bool damped = world.local_damping > 0.0;
  if (world.cell.periodic)
    return damped ? with.template operator()<true, true>()
                  : with.template operator()<false, true>();
  return damped ? with.template operator()<true, false>()
                : with.template operator()<false, false>();
}

// (P.orient is sized by integrate() before it is read: the force stage's move never tracks.)
template <int D>
GrainArrays<D> grain_arrays(World<D>& world) {
  auto& P = world.particles;
  return GrainArrays<D>{P.pos.data(),         P.vel.data(),    P.angvel.data(),
                        P.force.data(),       P.torque.data(), P.inv_mass.data(),
                        P.inv_inertia.data(), P.flags.data(),  P.orient.data()};
}

// The vector move kernel of the step's instruction set where it applies (no periodic cell, no
// orientations to track, AVX2 or AVX-512); null otherwise.
template <int D>
using MoveKernel = double (*)(const MoveConstants&, const MoveArrays&, std::size_t, std::size_t);
template <int D>
MoveKernel<D> vector_move(const World<D>& world) {
#if defined(__x86_64__) && defined(__GNUC__)
  const ContactPath path = contact_path();
  if (world.cell.periodic || world.track_orientation) return nullptr;
  if (path == ContactPath::kAvx512) return &move_kernel_avx512<D>;
  if (path == ContactPath::kAvx2) return &move_kernel_avx2<D>;
#endif
  (void)world;
  return nullptr;
}

template <int D>
MoveConstants move_constants(const World<D>& world) {
  MoveConstants c;
  c.dt = world.dt;
  c.alpha = world.local_damping;
  for (int k = 0; k < D; ++k) c.gravity[k] = world.gravity[k];
  c.left_alone = kClumpMember | kGhost;
  c.fixed = kFixed;
  return c;
}

template <int D>
MoveArrays move_arrays(const GrainArrays<D>& A) {
  return MoveArrays{
      as_doubles(A.pos),    as_doubles(A.vel), as_doubles(A.angvel), as_doubles(A.force),
      as_doubles(A.torque), A.inv_mass,        A.inv_inertia,        A.flags};
}

// The whole blocks of grains by the move kernel of the step's instruction set
// (integrate/move_kernel.hpp) where it applies; returns how many grains it moved (the rest
// go through the scalar loop) and the largest speed squared among them.
template <int D>
std::size_t move_blocks(World<D>& world, const GrainArrays<D>& A, double& vmax2) {
  vmax2 = 0.0;
  const MoveKernel<D> kernel = vector_move(world);
  if (kernel == nullptr) return 0;
  const MoveConstants c = move_constants(world);
  const MoveArrays m = move_arrays(A);
  const std::size_t n = world.particles.size(), whole = n - n % kMoveBlock;
  // The whole blocks by the force stage's slabs, in its fixed shares per thread
  // (base/slab_shares.hpp): a thread then moves mostly the grains whose forces it has just
  // added up, still in its core's cache. (Chunks in static halves moved the other thread's
  // slabs as often as not: on two threads of a 2-vCPU VM one half took twice the other's
  // time.) A block goes with the slab of its first grain. One term of the maximum per slab.
  const SlabPlan plan = world.slab_plan(n);
  world.slab_vmax2.assign(plan.count, 0.0);
  double* part = world.slab_vmax2.data();
  auto block_start = [whole](std::size_t i) {
    return std::min(whole, (i + kMoveBlock - 1) / kMoveBlock * kMoveBlock);
  };
  for_slabs(plan, world.threads, [&](std::size_t s, std::size_t first, std::size_t last) {
    const std::size_t b = block_start(first), e = block_start(last);
    if (b >= e) return;
    part[s] = kernel(c, m, b, e);
  });
  for (std::size_t s = 0; s < plan.count; ++s) vmax2 = std::max(vmax2, part[s]);
  return whole;
}

}  // namespace

template <int D>
double move_grain_range(World<D>& world, std::size_t first, std::size_t last) {
  const GrainArrays<D> A = grain_arrays(world);
  double vmax2 = 0.0;
  std::size_t from = first;
  if (const MoveKernel<D> kernel = vector_move(world)) {
    from = first + (last - first) / kMoveBlock * kMoveBlock;
    if (from > first) vmax2 = kernel(move_constants(world), move_arrays(A), first, from);
  }
  return std::max(vmax2, move_grains(world, A, from, last, false));
}

template <int D>
void integrate(World<D>& world) {
  const std::size_t n = world.particles.size();
  const double dt = world.dt;
  const bool periodic = world.cell.periodic;
  const typename Dim<D>::Tensor L = world.cell.vel_grad;
  double vmax2 = 0.0;
  if (world.grains_moved) {  // by the force stage, slab by slab
    for (const double v : world.slab_vmax2) vmax2 = std::max(vmax2, v);
    world.grains_moved = false;
  } else {
    auto& P = world.particles;
    if (world.track_orientation && P.orient.size() != n) P.orient.resize(n, Dim<D>::identity());
    const GrainArrays<D> arrays = grain_arrays(world);
    const std::size_t first = move_blocks(world, arrays, vmax2);
    vmax2 = std::max(vmax2, move_grains(world, arrays, first, n, n - first >= kParallelMin));
  }
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

template double move_grain_range<2>(World<2>&, std::size_t, std::size_t);
template double move_grain_range<3>(World<3>&, std::size_t, std::size_t);
template void integrate<2>(World<2>&);
template void integrate<3>(World<3>&);
template void move_walls<2>(World<2>&);
template void move_walls<3>(World<3>&);

}  // namespace geodem
