// The contact force stage on several threads, with results that depend neither on the
// number of threads nor on when the neighbour list was rebuilt.
//
// Each grain-grain pair is listed once, in the row of its lower index, and its force
// goes to both grains. The grains are cut into slabs: fixed ranges of indices whose
// length depends only on the grain count. The slabs run side by side; each runs its
// rows in index order. A force on a grain of the same slab is added at once; a force
// on a grain of a later slab (its index is higher) is kept in the slab's bucket for that
// later slab; the buckets are added afterwards, target slabs side by side, each target's
// in source-slab order (SlabCrossings, base/parallel.hpp). Every grain
// thus sums its forces in one fixed order: first those from its own slab's rows (by
// row), then those from earlier slabs (by slab, then row). Pairs listed but apart add
// nothing, so the list's skin and rebuilds do not change the order either. Sums over
// contacts (stress, wall forces, broken bonds) are kept per slab and added in slab
// order.
#include "contacts/contact_forces.hpp"

#include <algorithm>

#include "base/parallel.hpp"
#include "contacts/batched_pairs.hpp"
#include "contacts/contact_batch.hpp"
#include "contacts/contact_law.hpp"
#include "contacts/plane_walls.hpp"
#include "contacts/slab_tally.hpp"
#include "contacts/wall_rows.hpp"
#include "integrate/integrator.hpp"

namespace geodem {

namespace {

// Grain-grain contacts of the rows [first, last) (one slab). `Extras`: the contacts carry rolling
// springs and bond states (a separate instantiation, so that plain frictional packings pay nothing
// for them).
template <int D, bool Measure, bool Extras, bool Periodic>
void pair_rows(World<D>& world, std::size_t first, std::size_t last, SlabTally<D>& t,
               typename SlabCrossings<SlabCrossing<D>>::Writer crossing) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  auto& P = world.particles;
  auto& L = world.nlist;
  const double dt = world.dt;
  const std::size_t nmat = world.materials.size();
  // Raw pointers: the compiler then knows the arrays do not move inside the loops.
  const Vec* __restrict pos = P.pos.data();
  const Vec* __restrict vel = P.vel.data();
  const Rot* __restrict angvel = P.angvel.data();
  const double* __restrict radius = P.radius.data();
  const double* __restrict inv_mass = P.inv_mass.data();
  const std::uint16_t* __restrict material = P.material.data();
  Vec* __restrict force = P.force.data();
  Rot* __restrict torque = P.torque.data();
  const std::uint32_t* __restrict start = L.start.data();
  const std::uint32_t* __restrict other = L.other.data();
  TangentSpring<D>* __restrict spring = L.spring.data();
  ContactExtra<D>* __restrict extra = L.extra.data();
  const PairLaw* pair_laws = world.pair_laws.data();
  const double overlap_limit = world.overlap_limit;
  // With clumps: how many contacts share each collision (their dashpots split the mass).
  const std::uint16_t* share =
      world.collision_shares.pair.empty() ? nullptr : world.collision_shares.pair.data();
  const CellImage* image = Periodic ? L.image.data() : nullptr;
  const PeriodicCell<D>& cell = world.cell;
  // Each row runs in two passes over chunks of its pairs: the first measures every listed pair
  // and keeps those that touch (or are bonded), without a branch on the outcome; the second
  // computes their forces, in list order. Whether a listed pair touches is hard to predict,
  // and each wrong guess discarded the long chain of a contact force in flight; in the second
  // pass consecutive contacts run without a guess between them, so the processor overlaps
  // their chains. The forces and their order are those of a single pass.
  constexpr std::uint32_t kChunk = 32;
  std::uint32_t touching[kChunk];
  Vec branch[kChunk];  // d = x_j (+ image shift) - x_i of each touching pair
  double branch2[kChunk];
  for (std::size_t i = first; i < last; ++i) {
    const std::uint32_t b = start[i], e = start[i + 1];
    if (b == e) continue;
    const Vec xi = pos[i];
    const Vec vi = vel[i];
    const Rot wi = angvel[i];
    const double ri = radius[i], imi = inv_mass[i];
    const PairLaw* laws = pair_laws + material[i] * nmat;
    Vec fi = Vec::Zero();
    Rot ti = Dim<D>::zero_rot();
    for (std::uint32_t cb = b; cb < e; cb += kChunk) {
      const std::uint32_t ce = std::min(e, cb + kChunk);
      std::uint32_t n = 0;
      for (std::uint32_t k = cb; k < ce; ++k) {
        const std::uint32_t j = other[k];
        Vec d = pos[j] - xi;
        if constexpr (Periodic) {
          if (!image[k].home()) d += cell.shift(image[k]);
        }
        const double rs = ri + radius[j];
        const double dist2 = d.squaredNorm();
        bool bonded = false;
        if constexpr (Extras) bonded = extra[k].bonded;
        const bool apart = (dist2 >= rs * rs) & !bonded;
        touching[n] = k;
        branch[n] = d;
        branch2[n] = dist2;
        n += apart ? 0u : 1u;
        // Apart: the history ends (written only when there is one, to spare stores). The
        // conditions are combined without a jump so that the one branch is nearly always
        // the same way.
        if (apart & (spring_norm2<D>(spring[k]) != 0.0)) spring[k] = unloaded_spring<D>();
        if constexpr (Extras) {
          if (apart & ((Dim<D>::rot_norm2(extra[k].roll) != 0.0) | (extra[k].twist != 0.0)))
            extra[k] = ContactExtra<D>{};
        }
      }
      for (std::uint32_t c = 0; c < n; ++c) {
        const std::uint32_t k = touching[c];
        const std::uint32_t j = other[k];
        const Vec& d = branch[c];
        const double dist2 = branch2[c];
        const double rj = radius[j];
        const double rs = ri + rj;
        bool bonded = false;
        if constexpr (Extras) bonded = extra[k].bonded;
        bool imaged = false;
        if constexpr (Periodic) imaged = !image[k].home();
        const double dist = std::sqrt(dist2);
        const Vec nrm = d * (1.0 / dist);
        const double delta = rs - dist;
        if (delta > overlap_limit * std::min(ri, rj)) [[unlikely]]
          t.note_overlap(i, static_cast<std::int64_t>(j), delta / std::min(ri, rj));
        const double ai = ri - 0.5 * delta, aj = rj - 0.5 * delta;  // centre-to-contact lengths
        // Surface velocities at the contact point.
        Vec vrel =
            (vel[j] - Dim<D>::cross(angvel[j], aj * nrm)) - (vi + Dim<D>::cross(wi, ai * nrm));
        // Velocities are relative to the cell's affine field: the centres' relative velocity
        // gains L d.
        if constexpr (Periodic) vrel += cell.vel_grad * d;
        const PairLaw& law = laws[material[j]];
        double fn;
        Vec f;
        const double inv_msum = share ? (imi + inv_mass[j]) * share[k] : imi + inv_mass[j];
        if (!bonded) {
          f = contact_force<D>(law, ri, rj, inv_msum, nrm, delta, vrel, dt, spring[k], fn);
        } else {
          bool broken;
          f = bonded_contact_force<D>(law, ri, rj, inv_msum, nrm, delta, vrel, dt, spring[k], fn,
                                      broken);
          if (broken) {
            extra[k].bonded = 0;
            // A bond across a rank boundary breaks on both ranks: its row's owner counts it.
            if (!(P.flags[i] & kGhost)) ++t.broken_bonds;
            if (delta <= 0.0) {
              extra[k] = ContactExtra<D>{};
              continue;
            }
          }
        }
        fi -= f;
        // Torques: lever arms +ai n (grain i) and -aj n (grain j); the normal part gives none.
        const Rot tq = Dim<D>::cross(nrm, f);
        ti -= ai * tq;
        Rot tj = -(aj * tq);
        if constexpr (Extras) {
          if (law.rolling()) {
            const Rot m = rolling_moment<D>(law, tangential_stiffness(law, ri, rj, delta), ri, rj,
                                            nrm, Rot(angvel[j] - wi), dt, fn, extra[k]);
            tj += m;
            ti -= m;
          }
        }
        if (j < last) {  // same slab
          force[j] += f;
          torque[j] += tj;
        } else {
          crossing.push({f, tj, j});
        }
        if constexpr (Periodic) {
          if constexpr (!kFabricByGrain<D>) {
            t.cell_fabric += d * f.transpose();
          } else if (imaged) [[unlikely]] {
            t.cell_fabric += cell.shift(image[k]) * f.transpose();
          }
          const Vec kc = normal_stiffness(law, ri, rj, fn, delta) * d.cwiseProduct(nrm).cwiseAbs2();
          t.cell_stiffness += kc;
          if (t.exact.on && !(P.flags[i] & kGhost)) {
            t.exact.add_cell_stiffness(i, kc);
            if (imaged) t.exact.add_cell_fabric(cell.shift(image[k]), f);
          }
        }
        if constexpr (Measure) {
          t.stats.fabric_stress += d * f.transpose();
          t.stats.sum_force += f.norm();
          ++t.stats.contacts;
          const double energy = fn > 0.0 ? normal_energy(law, ri, rj, fn, delta) : 0.0;
          if (fn > 0.0) t.stats.elastic_energy += energy;
          if (t.exact.on && !(P.flags[i] & kGhost)) t.exact.add_contact(d, f, energy, false);
        }
      }
    }
    force[i] += fi;
    torque[i] += ti;
  }
}

// The contacts' sum of d f^T, d = x_j + shift - x_i and f the force on j, less the shifts'
// part: the sum over grains of x F^T, F each grain's total from its contacts (the forces
// hold nothing else when it runs). Per slab, in slab order, as every other sum.
template <int D>
void cell_fabric_of_grains(const World<D>& world, std::size_t first, std::size_t last,
                           SlabTally<D>& tally) {
  const auto& P = world.particles;
  typename Dim<D>::Tensor sum = Dim<D>::Tensor::Zero();
  for (std::size_t i = first; i < last; ++i) sum += P.pos[i] * P.force[i].transpose();
  tally.cell_fabric += sum;
}

// A decomposed cell's exact part of the same sum (ExactTally): the rank's own grains' x F^T,
// a clump member's x its clump's centre (cell_stress takes that correction in one process).
template <int D>
void exact_cell_fabric_of_grains(const World<D>& world, std::size_t first, std::size_t last,
                                 SlabTally<D>& tally) {
  const auto& P = world.particles;
  const auto& C = world.clumps;
  const bool clumps = !P.clump.empty();
  for (std::size_t i = first; i < last; ++i) {
    if (P.flags[i] & kGhost) continue;
    const bool member = clumps && P.clump[i] != kNoClump;
    tally.exact.add_cell_fabric(member ? C.pos[P.clump[i]] : P.pos[i], P.force[i]);
  }
}

// What one slab's task does in the pass over the pairs, and in the pass that finishes the slab
// (finish_slab). Set up once a step by the two passes' caller.
template <int D>
struct SlabPasses {
  SlabPlan plan;
  bool batched = false, one_law = false;             // pairs
  bool walls = false, planes = false, move = false;  // finishing
  double* vmax2 = nullptr;
};

template <int D>
SlabPasses<D> slab_passes(World<D>& world, bool measure, bool extras, bool periodic) {
  SlabPasses<D> p;
  p.plan = world.slab_plan(world.particles.size());
  world.slab_crossing.prepare(p.plan, world.threads);
  // Contacts without extras run in batches unless the scalar loop is asked for.
  p.batched = contact_path() != ContactPath::kScalar && batch_kernel_has(world.pair_laws);
  // (the vector gather pass runs outside a periodic cell only: no scan there)
  p.one_law = p.batched && !extras && !periodic && grains_of_one_material(world);
  p.walls = !world.walls.empty();
  p.planes = walls_by_plane_passes(world, measure, extras);
  p.move = world.move_in_force_stage;
  if (p.move) world.slab_vmax2.assign(p.plan.count, 0.0);
  p.vmax2 = world.slab_vmax2.data();
  return p;
}

// Slab s's grain-grain rows.
template <int D, bool Measure, bool Extras, bool Periodic>
void pair_slab(World<D>& world, const SlabPasses<D>& p, SlabTally<D>& tally, std::size_t s,
               std::size_t first, std::size_t last) {
  auto& P = world.particles;
  // The slab's forces start from zero here, in the task that adds to them first (a pass of
  // its own was one more parallel region a step).
  std::fill(P.force.begin() + static_cast<std::ptrdiff_t>(first),
            P.force.begin() + static_cast<std::ptrdiff_t>(last), Dim<D>::Vec::Zero());
  std::fill(P.torque.begin() + static_cast<std::ptrdiff_t>(first),
            P.torque.begin() + static_cast<std::ptrdiff_t>(last), Dim<D>::zero_rot());
  if constexpr (!Extras) {
    if (p.batched) {
      batched_pair_rows<D, Measure, Periodic>(world, first, last, tally,
                                              world.slab_crossing.slab(s), p.one_law);
      return;
    }
  }
  pair_rows<D, Measure, Extras, Periodic>(world, first, last, tally, world.slab_crossing.slab(s));
}

// What is left of slab s's grains once the pairs of every slab up to s are done (no later
// slab's row reaches them: a pair is listed in the row of its lower index): the forces from
// pairs of earlier slabs (SlabCrossings, in source-slab order), then in a periodic cell the
// slab's part of the sum of x F^T (the grains' forces then hold their pair contacts alone),
// then the wall contacts, then, when the step asks for it (world/step.cpp), the grains' move.
// Each grain gets its additions in the order the three passes gave. (The crossings' extra
// target, bodies numbered from the grain count up, stays empty here: every partner of a
// grain-grain pair is a grain.)
template <int D, bool Measure, bool Extras, bool Periodic>
void finish_slab(World<D>& world, const SlabPasses<D>& p, SlabTally<D>& tally, std::size_t s,
                 std::size_t first, std::size_t last) {
  auto& P = world.particles;
  world.slab_crossing.apply_to(s, [&P](const SlabCrossing<D>& c) {
    P.force[c.body] += c.a;
    P.torque[c.body] += c.b;
  });
  // (a decomposed cell's plain sum would be replaced by its exact one: not taken)
  if constexpr (Periodic) {
    if (world.domain)
      exact_cell_fabric_of_grains(world, first, last, tally);
    else if constexpr (kFabricByGrain<D>)
      cell_fabric_of_grains(world, first, last, tally);
  }
  if (p.walls) wall_rows<D, Measure, Extras>(world, first, last, tally, p.planes);
  // The slab's forces are complete and every pair is done (the only tasks that read other
  // slabs' grains): when the step allows it, move the slab's grains while in cache.
  if (p.move) p.vmax2[s] = move_grain_range(world, first, last);
}

// Slabs side by side: every slab's pairs, then every slab's finish, one parallel region each.
// On one thread each slab is finished right after its pairs, while its grains are in cache:
// the sums are the same, in the same order, since the slabs before it are done. Its crossing
// buckets are then empty, and their blocks go on to the later slabs' pairs: the buckets hold
// the crossings of about one slab at a time, not of all (at 200,000 spheres in a settled bed
// about 13 MB, 65 bytes a grain).
template <int D, bool Measure, bool Extras, bool Periodic>
void pairs_and_finish(World<D>& world, std::vector<SlabTally<D>>& tallies) {
  const SlabPasses<D> p = slab_passes(world, Measure, Extras, Periodic);
  SlabTally<D>* tally = tallies.data();
  if (slabs_on_threads(p.plan, world.threads)) {
    for_slabs(p.plan, world.threads, [&](std::size_t s, std::size_t first, std::size_t last) {
      pair_slab<D, Measure, Extras, Periodic>(world, p, tally[s], s, first, last);
    });
    for_slabs(p.plan, world.threads, [&](std::size_t s, std::size_t first, std::size_t last) {
      finish_slab<D, Measure, Extras, Periodic>(world, p, tally[s], s, first, last);
    });
  } else {
    for (std::size_t s = 0; s < p.plan.count; ++s) {
      const std::size_t first = p.plan.first(s), last = p.plan.last(s);
      pair_slab<D, Measure, Extras, Periodic>(world, p, tally[s], s, first, last);
      finish_slab<D, Measure, Extras, Periodic>(world, p, tally[s], s, first, last);
      world.slab_crossing.recycle(s);
    }
  }
  world.grains_moved = p.move;
}

}  // namespace

// A decomposed world: the walls' sums, the contact statistics and a periodic cell's sums are
// every rank's exact sums added over ranks (the rank's own, plain sums above are replaced).
template <int D>
void reduce_over_ranks(World<D>& world, std::vector<SlabTally<D>>& tallies, std::size_t slabs) {
  using Tally = ExactTally<D>;
  const std::size_t nw = world.walls.size();
  const bool measure = world.measure_this_step;
  static thread_local std::vector<ExactSum> sums;  // kept: the step allocates nothing
  // (last: the ranks that met an overlap beyond the limit, so that every rank stops)
  const std::size_t at_cell = nw * Tally::kPerWall + (measure ? Tally::kStats : 0);
  const bool periodic = world.cell.periodic;
  const std::size_t flag = at_cell + (periodic ? Tally::kCell : 0);
  sums.assign(flag + 1, ExactSum{});
  for (std::size_t s = 0; s < slabs; ++s) {
    const auto& t = tallies[s].exact;
    for (std::size_t k = 0; k < t.wall.size(); ++k) sums[k].add(t.wall[k]);
    for (std::size_t k = 0; k < t.stats.size(); ++k) sums[nw * Tally::kPerWall + k].add(t.stats[k]);
    tallies[s].exact.finish_rows();
    for (std::size_t k = 0; k < t.cell.size(); ++k) sums[at_cell + k].add(t.cell[k]);
  }
  for (std::size_t s = 0; s < slabs; ++s)
    if (tallies[s].overlap_offender >= 0) sums[flag].add(1.0);
  world.domain->sum(sums);
  world.overlap_elsewhere = sums[flag].value() > 0.0;
  for (std::size_t w = 0; w < nw; ++w) {
    for (int a = 0; a < D; ++a)
      world.walls[w].force[a] = sums[w * Tally::kPerWall + static_cast<std::size_t>(a)].value();
    world.walls[w].stiffness = sums[w * Tally::kPerWall + D].value();
    world.walls[w].dashpot = sums[w * Tally::kPerWall + D + 1].value();
  }
  if (periodic) Tally::read_cell(sums.data() + at_cell, world.cell_fabric, world.cell_stiffness);
  if (!measure) return;
  const ExactSum* st = sums.data() + nw * Tally::kPerWall;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) world.stats.fabric_stress(a, b) = st[a * D + b].value();
  world.stats.sum_force = st[D * D].value();
  world.stats.elastic_energy = st[D * D + 1].value();
  world.stats.contacts = static_cast<std::size_t>(st[D * D + 2].value());
  world.stats.wall_contacts = static_cast<std::size_t>(st[D * D + 3].value());
}

template <int D>
void compute_contact_forces(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  // Per-slab sums, kept between steps so that the step allocates nothing.
  static thread_local std::vector<SlabTally<D>> tallies;
  const std::size_t slabs = world.slab_plan(world.particles.size()).count;
  const std::size_t nw = world.walls.size();
  if (tallies.size() < slabs) tallies.resize(slabs);
  for (std::size_t s = 0; s < slabs; ++s) {
    auto& t = tallies[s];
    t.stats = ContactStats<D>{};
    t.broken_bonds = 0;
    t.overlap_offender = -1;
    t.wall_force.assign(nw, Vec::Zero());
    t.wall_stiffness.assign(nw, 0.0);
    t.wall_dashpot.assign(nw, 0.0);
    t.cell_stiffness = Vec::Zero();
    t.cell_fabric.setZero();
    t.exact.reset(world.domain != nullptr, nw, world.measure_this_step, world.cell.periodic);
  }
  // One instantiation per combination, so that a plain packing pays for no option.
  auto run = [&]<bool Measure, bool Extras>() {
    if (world.cell.periodic) {
      pairs_and_finish<D, Measure, Extras, true>(world, tallies);
    } else {
      pairs_and_finish<D, Measure, Extras, false>(world, tallies);
    }
  };
  const bool extras = world.contact_extras;
  if (world.measure_this_step) {
    if (extras) {
      run.template operator()<true, true>();
    } else {
      run.template operator()<true, false>();
    }
  } else if (extras) {
    run.template operator()<false, true>();
  } else {
    run.template operator()<false, false>();
  }
  // The slabs' sums, in slab order.
  for (auto& w : world.walls) {
    w.force = Vec::Zero();
    w.stiffness = 0.0;
    w.dashpot = 0.0;
  }
  if (world.measure_this_step) world.stats = ContactStats<D>{};
  world.cell_stiffness = Vec::Zero();
  world.cell_fabric.setZero();
  for (std::size_t s = 0; s < slabs; ++s) {
    const auto& t = tallies[s];
    if (world.measure_this_step) add_stats(world.stats, t.stats);
    world.broken_bonds += t.broken_bonds;
    world.cell_stiffness += t.cell_stiffness;
    world.cell_fabric += t.cell_fabric;
    if (world.overlap_offender < 0 && t.overlap_offender >= 0) {
      world.overlap_offender = t.overlap_offender;
      world.overlap_partner = t.overlap_partner;
      world.overlap_ratio = t.overlap_ratio;
    }
    for (std::size_t w = 0; w < nw; ++w) {
      world.walls[w].force += t.wall_force[w];
      world.walls[w].stiffness += t.wall_stiffness[w];
      world.walls[w].dashpot += t.wall_dashpot[w];
    }
  }
  if (world.domain) reduce_over_ranks(world, tallies, slabs);
}

template void compute_contact_forces<2>(World<2>&);
template void compute_contact_forces<3>(World<3>&);

}  // namespace geodem
