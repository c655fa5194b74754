// The pair loop of a slab in three passes over batches of touching contacts:
//   gather  rows in index order, pairs in list order: measure each listed pair; a pair apart
//           ends its history, a touching one is copied into the batch (branch, radii, masses,
//           velocities, spins, spring);
//   compute one kernel call for the batch (contacts/contact_batch.cpp), every contact in its
//           own vector lane;
//   add     the contacts in the batch's order, which is the list's: each force and torque
//           goes to the grains exactly as in the scalar loop (contacts/contact_forces.cpp),
//           the row's own sum to grain i when the next row starts.
// A batch holds one pair law (a change of law, as between materials, starts a new batch) and
// may end inside a row: the row's sums carry over to the next batch. Where one law holds for
// every pair, the gather pass runs in vector lanes (contacts/pair_gather.hpp) and keeps the
// same pairs in the same order.
#include "contacts/batched_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "contacts/batch_adds.hpp"
#include "contacts/contact_batch.hpp"
#include "contacts/contact_law.hpp"
#include "contacts/pair_gather.hpp"

namespace geodem {

namespace {

BatchLaw batch_law_of(const PairLaw& p) {
  return {p.law == LawKind::kHertz,
          p.constant_stiffness,
          p.per_unit_thickness,
          p.tangential_damping,
          p.kn,
          p.kt,
          p.e1r,
          p.e2r,
          p.kt_over_kn,
          p.mu,
          p.beta,
          p.hertz_damp,
          p.estar,
          p.gstar};
}

}  // namespace

bool batch_kernel_has(const std::vector<PairLaw>& laws) {
  return std::all_of(laws.begin(), laws.end(), [](const PairLaw& p) {
    // No default: a new law makes the compiler warn here (an error in CI builds) until the
    // kernel has its formulas or this returns false for it.
    switch (p.law) {
      case LawKind::kLinear:
      case LawKind::kHertz:
        return true;
    }
    return false;
  });
}

template <int D>
bool grains_of_one_material(const World<D>& world) {
  const auto& m = world.particles.material;
  return std::all_of(m.begin(), m.end(),
                     [first = m.empty() ? 0 : m.front()](std::uint16_t x) { return x == first; });
}

template bool grains_of_one_material<2>(const World<2>&);
template bool grains_of_one_material<3>(const World<3>&);

template <int D, bool Measure, bool Periodic>
void batched_pair_rows(World<D>& world, std::size_t first, std::size_t last, SlabTally<D>& t,
                       typename SlabCrossings<SlabCrossing<D>>::Writer crossing, bool one_law) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  constexpr int kRot = ContactBatch<D>::kRot;
  auto& P = world.particles;
  auto& L = world.nlist;
  const std::size_t nmat = world.materials.size();
  const Vec* __restrict pos = P.pos.data();
  const double* __restrict radius = P.radius.data();
  const std::uint16_t* __restrict material = P.material.data();
  Vec* __restrict force = P.force.data();
  Rot* __restrict torque = P.torque.data();
  const std::uint32_t* __restrict start = L.start.data();
  const std::uint32_t* __restrict other = L.other.data();
  TangentSpring<D>* __restrict spring = L.spring.data();
  const std::uint16_t* share =
      world.collision_shares.pair.empty() ? nullptr : world.collision_shares.pair.data();
  const CellImage* image = Periodic ? L.image.data() : nullptr;
  const PeriodicCell<D>& cell = world.cell;
  const double overlap_limit = world.overlap_limit;

  // Set once: the lanes a kernel computes beyond the batch's end then index the slab's first
  // grain and contact, or an earlier contact of the slab: data of this slab's task alone (grain
  // 0 and pair 0 belong to the first slab's task, which may be writing pair 0's spring).
  ContactBatch<D> batch{};
  std::fill(std::begin(batch.i), std::end(batch.i), static_cast<std::int64_t>(first));
  std::fill(std::begin(batch.j), std::end(batch.j), static_cast<std::int64_t>(first));
  std::fill(std::begin(batch.k), std::end(batch.k), static_cast<std::int64_t>(start[first]));
  batch.overlap_limit = overlap_limit;
  const BatchGrains grains{as_doubles(P.pos.data()),
                           as_doubles(P.vel.data()),
                           as_doubles(P.angvel.data()),
                           radius,
                           P.inv_mass.data(),
                           as_doubles(L.spring.data()),
                           share != nullptr};
  int n = 0;
  const PairLaw* law = nullptr;  // the batch's
  BatchLaw batch_law;
  // The row whose own sums are open (none yet: `last`), and those sums.
  OpenRowSums<D> open{last};
  double* const force_d = as_doubles(force);
  double* const torque_d = as_doubles(torque);
  auto close_row = [&] { close_open_row(open, last, force_d, torque_d); };

  auto add_batch = [&] {
    batch_contact_forces<D, Periodic>(batch_law, grains, world.dt, batch, n);
    if (!Measure && !Periodic && !batch.overlap_seen) {
      add_plain_batch<D>(batch, n, last, force_d, torque_d, open, crossing);
      n = 0;
      return;
    }
    for (int c = 0; c < n; ++c) {
      const auto i = static_cast<std::size_t>(batch.i[c]);
      const auto j = static_cast<std::uint32_t>(batch.j[c]);
      const auto k = static_cast<std::uint32_t>(batch.k[c]);
      if (i != open.row) {
        close_row();
        open.row = i;
      }
      const double delta = batch.delta[c];
      if (batch.overlap_seen) [[unlikely]] {
        const double m = std::min(radius[i], radius[j]);
        if (delta > overlap_limit * m) t.note_overlap(i, static_cast<std::int64_t>(j), delta / m);
      }
      Vec f, d;
      Rot tqi, tj;
      for (int a = 0; a < D; ++a) {
        f[a] = batch.f[a][c];
        d[a] = batch.d[a][c];
      }
      if constexpr (D == 3) {
        for (int a = 0; a < kRot; ++a) {
          tqi[a] = batch.tqi[a][c];
          tj[a] = batch.tj[a][c];
        }
      } else {
        tqi = batch.tqi[0][c];
        tj = batch.tj[0][c];
      }
      for (int a = 0; a < D; ++a) open.f[a] -= f[a];
      if constexpr (D == 3) {
        for (int a = 0; a < kRot; ++a) open.t[a] -= tqi[a];
      } else {
        open.t[0] -= tqi;
      }
      if (j < last) {  // same slab
        force[j] += f;
        torque[j] += tj;
      } else {
        crossing.push({f, tj, j});
      }
      const double fn = batch.fn[c];
      [[maybe_unused]] const double ri = radius[i], rj = radius[j];  // for the sums below
      if constexpr (Periodic) {
        const Vec nrm = d * (1.0 / std::sqrt(d.squaredNorm()));
        if constexpr (!kFabricByGrain<D>) {
          t.cell_fabric += d * f.transpose();
        } else if (!image[k].home()) [[unlikely]] {
          t.cell_fabric += cell.shift(image[k]) * f.transpose();
        }
        const Vec kc = normal_stiffness(*law, ri, rj, fn, delta) * d.cwiseProduct(nrm).cwiseAbs2();
        t.cell_stiffness += kc;
        if (t.exact.on && !(P.flags[i] & kGhost)) {  // a decomposed cell (slab_tally.hpp)
          t.exact.add_cell_stiffness(i, kc);
          if (!image[k].home()) t.exact.add_cell_fabric(cell.shift(image[k]), f);
        }
      }
      if constexpr (Measure) {
        const double energy = fn > 0.0 ? normal_energy(*law, ri, rj, fn, delta) : 0.0;
        if (t.exact.on && !(P.flags[i] & kGhost)) t.exact.add_contact(d, f, energy, false);
        t.stats.fabric_stress += d * f.transpose();
        t.stats.sum_force += f.norm();
        ++t.stats.contacts;
        if (fn > 0.0) t.stats.elastic_energy += energy;
      }
    }
    n = 0;
  };

  if constexpr (!Periodic) {
    const ContactPath path = contact_path();
    if (one_law && share == nullptr && pair_gather_has(path) && start[first] < start[last]) {
      const std::size_t m = material[first];
      law = world.pair_laws.data() + m * nmat + m;
      batch_law = batch_law_of(*law);
      const PairGatherInput in{as_doubles(P.pos.data()),
                               radius,
                               start,
                               other,
                               as_doubles(L.spring.data()),
                               static_cast<std::uint32_t>(L.other.size())};
      PairWindow w(start, first, last);
      batch.measured = true;
      while (w.next < w.end) {
        n = gather_touching<D>(path, in, w, batch, n);
        if (w.next < w.end) add_batch();  // the batch is full
      }
      if (n > 0) add_batch();
      close_row();
      return;
    }
  }
  const bool one_material = nmat == 1;
  for (std::size_t i = first; i < last; ++i) {
    const std::uint32_t b = start[i], e = start[i + 1];
    if (b == e) continue;
    const Vec xi = pos[i];
    const double ri = radius[i];
    const PairLaw* laws = world.pair_laws.data() + material[i] * nmat;
    for (std::uint32_t k = b; k < e; ++k) {
      const std::uint32_t j = other[k];
      Vec d = pos[j] - xi;
      if constexpr (Periodic) {
        if (!image[k].home()) d += cell.shift(image[k]);
      }
      const double rj = radius[j];
      const double rs = ri + rj;
      const double dist2 = d.squaredNorm();
      // Every listed pair is written into the batch's next slot, which only a touching pair
      // keeps: whether a pair touches is hard to predict, and a branch on it would discard the
      // work in flight at each wrong guess.
      const bool apart = dist2 >= rs * rs;
      // Apart: the history ends where there is one. The spring is written back either way,
      // its own bits or +0 through a mask, so that nothing waits on a guess of `apart`.
      const bool ends = apart & (spring_norm2<D>(spring[k]) != 0.0);
      keep_or_clear_spring<D>(spring[k], std::uint64_t{0} - static_cast<std::uint64_t>(!ends));
      const PairLaw* pair_law = one_material ? laws : laws + material[j];
      if (!apart & (pair_law != law)) [[unlikely]] {
        if (n > 0) add_batch();
        law = pair_law;
        batch_law = batch_law_of(*law);
      }
      if constexpr (Periodic) {
        // Velocities are relative to the cell's affine field: the centres' relative
        // velocity gains L d.
        const Vec shift = cell.vel_grad * d;
        for (int a = 0; a < D; ++a) {
          batch.d[a][n] = d[a];
          batch.vel_shift[a][n] = shift[a];
        }
      }
      if (share) batch.share[n] = share[k];
      batch.i[n] = static_cast<std::int64_t>(i);
      batch.j[n] = j;
      batch.k[n] = k;
      n += apart ? 0 : 1;
      if (n == ContactBatch<D>::kSize) add_batch();
    }
  }
  if (n > 0) add_batch();
  close_row();
}

#define GEODEM_BATCHED_PAIR_ROWS(D, M, P)                                                      \
  template void batched_pair_rows<D, M, P>(World<D>&, std::size_t, std::size_t, SlabTally<D>&, \
                                           SlabCrossings<SlabCrossing<D>>::Writer, bool);
GEODEM_BATCHED_PAIR_ROWS(2, false, false)
GEODEM_BATCHED_PAIR_ROWS(2, false, true)
GEODEM_BATCHED_PAIR_ROWS(2, true, false)
GEODEM_BATCHED_PAIR_ROWS(2, true, true)
GEODEM_BATCHED_PAIR_ROWS(3, false, false)
GEODEM_BATCHED_PAIR_ROWS(3, false, true)
GEODEM_BATCHED_PAIR_ROWS(3, true, false)
GEODEM_BATCHED_PAIR_ROWS(3, true, true)
#undef GEODEM_BATCHED_PAIR_ROWS

}  // namespace geodem
