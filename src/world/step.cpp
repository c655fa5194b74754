// The time step as a fixed pipeline of named, timed stages:
//
//   1. neighbour search   rebuild the Verlet list when a grain or wall moved half the skin;
//                         then, every update_interval steps, the automatic time step
//   2. contact forces     grain-grain, grain-wall and grain-spar laws; wall reactions;
//                         measurements
//   3. structures         spar chains: element tensions, bending at nodes
//   4. controllers        servo walls, radius growth, ... (once each)
//   5. integration        leapfrog with local damping (grains, clumps, spar nodes);
//                         walls move; time advances
//   6. recorders          history rows, snapshots (outside the engine, by callback)
//
// Each stage lives in its concept's folder; this file only orders and times them.
#include "world/step.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "base/error.hpp"
#include "base/parallel.hpp"
#include "broadphase/neighbour_search.hpp"
#include "clumps/collision_shares.hpp"
#include "contacts/contact_forces.hpp"
#include "integrate/critical_timestep.hpp"
#include "integrate/integrator.hpp"
#include "structures/spar_contacts.hpp"
#include "structures/spar_dynamics.hpp"

namespace geodem {

namespace {

// Adds the wall time of a scope to one stage's total.
template <int D>
class ScopedStage {
 public:
  ScopedStage(World<D>& w, Stage s) : world_(w), stage_(s) {}
  ~ScopedStage() {
    world_.stage_seconds[static_cast<int>(stage_)] +=
        std::chrono::duration<double>(Clock::now() - t0_).count();
  }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  using Clock = std::chrono::steady_clock;
  World<D>& world_;
  Stage stage_;
  Clock::time_point t0_ = Clock::now();
};

// True when a grain, wall or spar node may have moved far enough that a pair not
// listed could now touch: 2 x (largest grain displacement) or grain + wall (or node)
// displacement beyond the skin. A point of an element moves at most as far as its
// farther node. The cheap velocity bound is refined by an exact pass first.
// A decomposed world's bound on the grains' displacement grows by the largest move over all
// ranks (one message, which also carries a build asked for): true when a build was asked for.
template <int D>
bool grow_bound_over_ranks(World<D>& world) {
  const double inf = std::numeric_limits<double>::infinity();
  const double moved =
      -world.domain->min_over_ranks(-(world.rebuild_needed ? inf : world.last_move));
  world.last_move = 0.0;
  if (moved == inf) return true;
  world.disp_bound += moved;
  return false;
}

template <int D>
bool list_expired(World<D>& world) {
  const auto& P = world.particles;
  const auto n = static_cast<std::ptrdiff_t>(P.size());
  const double skin = world.nlist.skin;
  if (world.cell.periodic) {
    // Displacements from the affine motion of the cell (u = x - F x_build), and the
    // strain that brings grains a reach apart closer (world/periodic_cell.hpp).
    const double closing = world.cell.strain_since_build() * world.cell.reach_at_build;
    auto expired = [&](double u) { return 2.0 * u + closing > skin; };
    if (world.domain && grow_bound_over_ranks(world)) return true;  // (as for walls below)
    if (!expired(world.disp_bound + world.radius_growth)) return false;
    const typename Dim<D>::Tensor F = world.cell.h * world.cell.h_at_build.inverse();
    // (a maximum: the same in any order)
    const double d2 = extreme_over_indices<true>(
        n, world.threads, P.size() >= kParallelMin, 0.0, [&](std::ptrdiff_t i) {
          const auto k = static_cast<std::size_t>(i);
          return (P.pos[k] - F * P.pos_at_build[k]).squaredNorm();
        });
    world.disp_bound = std::sqrt(d2);
    if (world.domain) world.disp_bound = -world.domain->min_over_ranks(-world.disp_bound);
    return expired(world.disp_bound + world.radius_growth);
  }
  double wall_disp = spar_max_displacement(world);
  for (const auto& w : world.walls) wall_disp = std::max(wall_disp, w.displacement.norm());
  auto expired = [&](double d) { return 2.0 * d > skin || d + wall_disp > skin; };
  if (world.domain) {
    // Every rank takes the same decision from the same numbers, as one rank would: the bound
    // grows by the largest move over all ranks (one message, which also carries a build
    // asked for), and the exact pass is the largest over all ranks. (A rank's own bound and
    // exact pass would not do: a member of a growing clump moves beyond its velocity's
    // bound, so the exact pass could expire on one rank and never be reached on another.)
    if (grow_bound_over_ranks(world)) return true;
    if (!expired(world.disp_bound + world.radius_growth)) return false;
  } else if (!expired(world.disp_bound + world.radius_growth)) {
    return false;
  }
  // (a maximum: the same in any order)
  const double d2 = extreme_over_indices<true>(
      n, world.threads, P.size() >= kParallelMin, 0.0, [&](std::ptrdiff_t i) {
        const auto k = static_cast<std::size_t>(i);
        return (P.pos[k] - P.pos_at_build[k]).squaredNorm();
      });
  world.disp_bound = std::sqrt(d2);
  if (world.domain) world.disp_bound = -world.domain->min_over_ranks(-world.disp_bound);
  return expired(world.disp_bound + world.radius_growth);
}

// Whether the force stage may move each slab's grains as soon as its forces are complete
// (contacts/contact_forces.cpp), instead of a pass of their own after the controllers: when
// nothing between the two adds to a grain's force or reads a grain (no spar chain, no clump, no
// decomposed domain, no periodic cell whose stress a servo reads, no orientation to track, and
// controllers of walls alone). The grains then move in cache, with one parallel region less a
// step; the same bits either way.
template <int D>
bool may_move_in_force_stage(const World<D>& world) {
  if (!world.spars.empty() || !world.particles.clump.empty() || world.domain ||
      world.cell.periodic || world.track_orientation)
    return false;
  for (const auto& c : world.controllers)
    if (!c->walls_only()) return false;
  return true;
}

}  // namespace

template <int D>
void update_timestep(World<D>& world) {
  if (!world.auto_dt) return;
  double dt = critical_timestep(world);
  if (world.domain) dt = world.domain->min_over_ranks(dt);
  if (std::isfinite(dt) && dt > 0.0) {
    world.dt = dt;
  } else if (!(dt > 0.0)) {  // zero or NaN: the run cannot advance (+inf: keep the last step)
    throw InstabilityError(
        "the critical time step is " + std::to_string(dt) + " at step " +
        std::to_string(world.step) +
        "; likely cause: contact stiffness out of proportion to the grains' masses (check "
        "young / kn and density)");
  }
}

// What to change about the time step, in the engine's terms (the runner names its keys).
template <int D>
std::string dt_advice(const World<D>& world) {
  return world.auto_dt ? "lower the automatic time step's safety factor (now " +
                             std::to_string(world.dt_safety) + ")"
                       : "use the automatic time step, or a smaller fixed one";
}

namespace {
template <int D>
void check_finite_here(const World<D>& world) {
  const auto& P = world.particles;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const bool ok = P.pos[i].allFinite() && P.vel[i].allFinite() &&
                    std::isfinite(Dim<D>::rot_norm2(P.angvel[i]));
    if (!ok)
      throw InstabilityError(
          "non-finite state at step " + std::to_string(world.step) +
          " (t = " + std::to_string(world.time) + " s) on grain " + std::to_string(P.id[i]) +
          "; likely cause: time step too large for the contact stiffness (dt = " +
          std::to_string(world.dt) + " s): " + dt_advice(world) + ", or lower the stiffness");
  }
  // Runaway motion: a contact that closes or slides by half a radius in one step is past
  // what the contact law resolves (the kinetic energy then grows without bound). Grains in
  // free flight, or moving together, may be that fast. Candidates first: a relative speed
  // that large needs one of the two grains at half of it (against the smallest radius).
  std::vector<std::uint8_t> fast;
  auto too_fast = [&](const typename Dim<D>::Vec& v, double r) {
    return v.norm() * world.dt > 0.5 * r;
  };
  double rmin = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < P.size(); ++i) rmin = std::min(rmin, P.radius[i]);
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.vel[i].norm() * world.dt > 0.25 * rmin) {
      if (fast.empty()) fast.assign(P.size(), 0);
      fast[i] = 1;
    }
  auto runaway = [&](std::size_t i, const std::string& partner, double speed) {
    throw InstabilityError(
        "runaway grain " + std::to_string(P.id[i]) + " against " + partner + " at step " +
        std::to_string(world.step) + " (t = " + std::to_string(world.time) +
        " s): relative speed " + std::to_string(speed) + " m/s, " +
        std::to_string(speed * world.dt / P.radius[i]) +
        " radii per step; likely cause: the kinetic energy grows without bound (time step too "
        "large for the stiffness, dt = " +
        std::to_string(world.dt) + " s, or a servo gain too high)");
  };
  if (!fast.empty()) {
    const auto& L = world.nlist;
    for (std::size_t i = 0; i + 1 < L.start.size() && i < P.size(); ++i) {
      for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
        const std::size_t j = L.other[k];
        if (!(fast[i] || fast[j])) continue;
        const double reach = P.radius[i] + P.radius[j];
        const auto rel = (P.vel[i] - P.vel[j]).eval();
        if (world.branch(i, j, k).squaredNorm() < reach * reach &&
            too_fast(rel, std::min(P.radius[i], P.radius[j])))
          runaway(fast[i] ? i : j, "grain " + std::to_string(P.id[fast[i] ? j : i]), rel.norm());
      }
    }
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (!fast[i]) continue;
      for (const auto& wall : world.walls) {
        typename Dim<D>::Vec q;
        const auto rel = (P.vel[i] - wall.velocity).eval();
        if (wall_closest(wall, P.pos[i], q) && (P.pos[i] - q).norm() < P.radius[i] &&
            too_fast(rel, P.radius[i]))
          runaway(i, "wall '" + wall.name + "'", rel.norm());
      }
    }
  }
  // Escape: a grain wholly behind a plane wall went through it between two contacts.
  for (const auto& wall : world.walls) {
    if (wall.kind != WallKind::kPlane) continue;
    for (std::size_t i = 0; i < P.size(); ++i)
      if ((P.pos[i] - wall.point).dot(wall.normal) < -P.radius[i])
        throw InstabilityError(
            "grain " + std::to_string(P.id[i]) + " escaped through wall '" + wall.name +
            "' at step " + std::to_string(world.step) + " (t = " + std::to_string(world.time) +
            " s); likely cause: time step too large (dt = " + std::to_string(world.dt) +
            " s) or contact stiffness too low for the load");
  }
  const auto& S = world.spars;
  for (std::size_t i = 0; i < S.nodes(); ++i)
    if (!S.pos[i].allFinite() || !S.vel[i].allFinite())
      throw InstabilityError("non-finite state at step " + std::to_string(world.step) +
                             " on node " + std::to_string(i) +
                             " of the spar chains; likely cause: time step too large for the "
                             "chain's stiffness J or bending stiffness (dt = " +
                             std::to_string(world.dt) + " s): " + dt_advice(world) +
                             ", or raise the nodes' mass");
}

}  // namespace

template <int D>
void check_finite(const World<D>& world) {
  if (!world.domain) return check_finite_here(world);
  // A decomposed domain: every rank stops, with the first rank's diagnosis.
  std::string here;
  try {
    check_finite_here(world);
  } catch (const InstabilityError& e) {
    here = e.what();
  }
  const std::string first = world.domain->first_text(here);
  if (!first.empty()) throw InstabilityError(first);
}

template <int D>
std::string overlap_message(const World<D>& world) {
  const auto& P = world.particles;
  const std::int64_t j = world.overlap_partner;
  // Partners: a grain (j >= 0), a wall (-1 - index), a spar element (-1 - walls - index).
  const std::size_t other = static_cast<std::size_t>(-1 - j);
  const std::string partner =
      j >= 0 ? "grain " + std::to_string(P.id[static_cast<std::size_t>(j)])
      : other < world.walls.size()
          ? "wall '" + world.walls[other].name + "'"
          : "spar element " + std::to_string(other - world.walls.size()) + " of chain '" +
                world.spars.chains[world.spars.chain_of[other - world.walls.size()]].name + "'";
  return "overlap of " + std::to_string(static_cast<int>(100.0 * world.overlap_ratio)) +
         " % of the radius between grain " +
         std::to_string(P.id[static_cast<std::size_t>(world.overlap_offender)]) + " and " +
         partner + " at step " + std::to_string(world.step) +
         " (t = " + std::to_string(world.time) +
         " s); likely cause: time step too large (dt = " + std::to_string(world.dt) +
         " s: " + dt_advice(world) + ") or contact stiffness too low for the load";
}

template <int D>
void step(World<D>& world) {
  {
    ScopedStage<D> t(world, Stage::kNeighbours);
    // (a decomposed world's check is itself taken over the ranks: list_expired)
    const bool rebuild =
        world.domain ? list_expired(world) : world.rebuild_needed || list_expired(world);
    if (rebuild) {
      if (world.domain) world.domain->before_build(world);
      // A build is a run's peak of memory (the old rows and the new ones are both resident).
      // The forces and torques are set afresh after it, and the positions at the build at its
      // end: their arrays are given back while it runs (72 bytes a grain in 3D), unless views
      // of them exist (Python's numpy arrays) or the last build found its scratch small enough
      // to keep (broadphase/neighbour_search). (A decomposed domain keeps the positions: its
      // grains carry them between ranks and its checkpoints rebuild from them, domain/.)
      auto& P = world.particles;
      const bool give_back = !P.stable_buffers && !world.keep_build_scratch;
      if (give_back) {
        std::vector<typename Dim<D>::Vec>().swap(P.force);
        std::vector<typename Dim<D>::Rot>().swap(P.torque);
        if (!world.domain) std::vector<typename Dim<D>::Vec>().swap(P.pos_at_build);
      }
      build_neighbour_list(world);
      if (give_back) {
        P.force.resize(P.size());
        P.torque.resize(P.size());
      }
    }
  }
  // After the neighbour search, so that the first automatic step sees the contacts.
  if (world.dt <= 0.0 || (world.auto_dt && world.step % world.dt_update_interval == 0)) {
    update_timestep(world);
  }
  {
    ScopedStage<D> t(world, Stage::kContactForces);
    // (the contact stage sets every grain's force and torque: no pass of its own zeroes them)
    update_collision_shares(world);
    world.move_in_force_stage = may_move_in_force_stage(world);
    compute_contact_forces(world);
    world.move_in_force_stage = false;
    compute_spar_contacts(world);
    if (world.overlap_offender >= 0 || world.overlap_elsewhere) {
      const std::string here = world.overlap_offender >= 0 ? overlap_message(world) : "";
      // Every rank of a decomposed domain stops here, with the diagnosis of the first that met it.
      throw InstabilityError(world.domain ? world.domain->first_text(here) : here);
    }
  }
  if (!world.spars.empty()) {
    ScopedStage<D> t(world, Stage::kStructures);
    spar_element_forces(world);
  }
  {
    ScopedStage<D> t(world, Stage::kControllers);
    for (auto& c : world.controllers) c->apply(world);
  }
  {
    ScopedStage<D> t(world, Stage::kIntegration);
    integrate(world);
    move_walls(world);
    if (world.domain) world.domain->after_integration(world);
    if (world.cell.periodic) world.cell.deform(world.dt);
    world.time += world.dt;
    ++world.step;
    if (world.step % 1000 == 0) check_finite(world);
  }
}

template void step<2>(World<2>&);
template void step<3>(World<3>&);
template void update_timestep<2>(World<2>&);
template void update_timestep<3>(World<3>&);
template void check_finite<2>(const World<2>&);
template void check_finite<3>(const World<3>&);

}  // namespace geodem
