// Ranks of a decomposed domain (domain/slab_domain.hpp) as threads of one test process that
// pass their messages through shared memory (ThreadComm), so that the migration, ghost and
// history code runs in the ordinary and the sanitizer builds; and what the domain tests
// compare: every grain's state by id, and the sums every rank holds.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "domain/slab_domain.hpp"
#include "measure/measurements.hpp"
#include "test_util.hpp"
#include "world/world_state.hpp"

namespace geodem::test {

// Messages between `size` threads: each call is a collective step all of them take.
struct Hub {
  explicit Hub(int n) : size(n), sync(n), down(n), up(n), values(n), sums(n), gathered(n) {}
  int size;
  std::barrier<> sync;
  std::vector<Bytes> down, up;
  std::vector<double> values;
  std::vector<std::vector<ExactSum>> sums;
  std::vector<Bytes> gathered;
};

class ThreadComm final : public DomainComm {
 public:
  ThreadComm(Hub& hub, int rank) : hub_(hub), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return hub_.size; }
  void exchange(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                Bytes& from_upper) override {
    const auto r = static_cast<std::size_t>(rank_);
    hub_.down[r] = to_lower, hub_.up[r] = to_upper;
    hub_.sync.arrive_and_wait();
    const bool closed = ring && hub_.size > 1;  // a periodic cell's slabs
    const auto last = static_cast<std::size_t>(hub_.size - 1);
    from_lower = rank_ > 0 ? hub_.up[r - 1] : closed ? hub_.up[last] : Bytes{};
    from_upper = r < last ? hub_.down[r + 1] : closed ? hub_.down[0] : Bytes{};
    hub_.sync.arrive_and_wait();
  }
  double max(double here) override { return reduce(here, true); }
  double min(double here) override { return reduce(here, false); }
  void sum(std::vector<ExactSum>& sums) override {
    hub_.sums[static_cast<std::size_t>(rank_)] = sums;
    hub_.sync.arrive_and_wait();
    for (std::size_t k = 0; k < sums.size(); ++k) {
      ExactSum total;
      for (const auto& s : hub_.sums) total.add(s[k]);
      sums[k] = total;
    }
    hub_.sync.arrive_and_wait();
  }
  Bytes gather(const Bytes& here) override {
    Bytes all = all_gather(here);
    return rank_ == 0 ? all : Bytes{};
  }
  Bytes all_gather(const Bytes& here) override {
    hub_.gathered[static_cast<std::size_t>(rank_)] = here;
    hub_.sync.arrive_and_wait();
    Bytes all;
    for (const auto& b : hub_.gathered) all.insert(all.end(), b.begin(), b.end());
    hub_.sync.arrive_and_wait();
    return all;
  }

 private:
  double reduce(double here, bool largest) {
    hub_.values[static_cast<std::size_t>(rank_)] = here;
    hub_.sync.arrive_and_wait();
    const auto [lo, hi] = std::minmax_element(hub_.values.begin(), hub_.values.end());
    const double v = largest ? *hi : *lo;
    hub_.sync.arrive_and_wait();
    return v;
  }
  Hub& hub_;
  int rank_;
};

// What the contact stage summed over the whole domain: the walls' forces, stiffnesses and
// the contact statistics of the last step; and the measurements over the grains.
template <int D>
struct Sums {
  std::vector<typename Dim<D>::Vec> force;
  std::vector<double> stiffness;
  typename Dim<D>::Tensor fabric;
  double sum_force, energy;
  std::size_t contacts, wall_contacts;
  // Measurements (measure/measurements.hpp), over the whole domain on every rank.
  double kinetic, unbalanced, volume, gravity;
  std::size_t bodies, bonds;
};
template <int D>
Sums<D> sums_of(const World<D>& w) {
  Sums<D> s{{},
            {},
            w.stats.fabric_stress,
            w.stats.sum_force,
            w.stats.elastic_energy,
            w.stats.contacts,
            w.stats.wall_contacts,
            kinetic_energy(w),
            unbalanced_force_ratio(w),
            solid_volume(w),
            gravity_energy(w),
            body_count(w),
            intact_bonds(w)};
  for (const auto& wall : w.walls)
    s.force.push_back(wall.force), s.stiffness.push_back(wall.stiffness);
  return s;
}
// Bitwise (exact sums of ranks) or within `rel` of the largest component (a one-process run
// sums in its own order).
template <int D>
void expect_sums(const Sums<D>& a, const Sums<D>& b, double rel) {
  auto near = [rel](double x, double y, double scale) {
    return rel == 0.0 ? x == y : std::abs(x - y) <= rel * scale;
  };
  for (std::size_t k = 0; k < a.force.size(); ++k) {
    const double scale = a.force[k].cwiseAbs().maxCoeff() + 1e-300;
    for (int c = 0; c < D; ++c)
      EXPECT_TRUE(near(a.force[k][c], b.force[k][c], scale))
          << "wall " << k << ": " << a.force[k][c] << " against " << b.force[k][c];
    EXPECT_TRUE(near(a.stiffness[k], b.stiffness[k], a.stiffness[k])) << "wall " << k;
  }
  const double fs = a.fabric.cwiseAbs().maxCoeff();
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < D; ++c) EXPECT_TRUE(near(a.fabric(r, c), b.fabric(r, c), fs));
  EXPECT_TRUE(near(a.sum_force, b.sum_force, a.sum_force));
  EXPECT_TRUE(near(a.energy, b.energy, a.energy));
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.wall_contacts, b.wall_contacts);
  EXPECT_TRUE(near(a.kinetic, b.kinetic, a.kinetic));
  EXPECT_TRUE(near(a.unbalanced, b.unbalanced, a.unbalanced));
  EXPECT_TRUE(near(a.volume, b.volume, a.volume));
  EXPECT_TRUE(near(a.gravity, b.gravity, std::abs(a.gravity)));
  EXPECT_EQ(a.bodies, b.bodies);
  EXPECT_EQ(a.bonds, b.bonds);
}

// Every grain's state by id, from its owner: the grains of all ranks in one table.
template <int D>
struct Grain {
  typename Dim<D>::Vec pos, vel;
  typename Dim<D>::Rot angvel;
  bool seen = false;
};
template <int D>
std::vector<Grain<D>> by_id(const std::vector<World<D>>& parts, std::size_t n,
                            std::size_t& ghosts) {
  std::vector<Grain<D>> g(n);
  ghosts = 0;
  for (const auto& w : parts) {
    const auto& P = w.particles;
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.flags[i] & kGhost) {
        ++ghosts;
        continue;
      }
      EXPECT_FALSE(g[P.id[i]].seen) << "grain " << P.id[i] << " owned twice";
      g[P.id[i]] = {P.pos[i], P.vel[i], P.angvel[i], true};
    }
  }
  return g;
}

template <int D>
std::size_t ghosts_in(const std::vector<World<D>>& parts) {
  std::size_t g = 0;
  for (const auto& w : parts)
    for (auto f : w.particles.flags) g += (f & kGhost) != 0;
  return g;
}

template <int D>
void expect_same(const std::vector<Grain<D>>& a, const std::vector<Grain<D>>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].seen, b[k].seen) << "grain " << k << " owned in one run only";
    if (!a[k].seen) continue;  // (removed in both)
    ASSERT_TRUE(a[k].pos == b[k].pos) << "grain " << k;
    ASSERT_TRUE(a[k].vel == b[k].vel) << "grain " << k;
    ASSERT_TRUE(a[k].angvel == b[k].angvel) << "grain " << k;
  }
}

// A checkpoint of a decomposed run as the scene runner writes it: `ranks` ranks each make the
// world (make()), take their slab and advance it (run(world)); rank 0 then holds the whole
// domain (SlabDomain::checkpoint) and saves it as world-state and domain bytes. The counts are
// what the tests assert on.
struct SavedDomain {
  std::string world, domain;
  std::size_t grains = 0, pairs = 0, spars = 0, clumps = 0, clump_ghosts = 0;
};
template <int D, class Make, class Run>
SavedDomain checkpoint_on_ranks(int ranks, Make&& make, Run&& run) {
  SavedDomain out;
  Hub hub(ranks);
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      World<D> w = make();
      auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
      run(w);
      DomainCheckpoint<D> saved;
      Clumps<D> clumps;
      Particles<D> all = d->checkpoint(w, saved, clumps);
      const std::uint64_t broken = broken_bond_count(w);
      if (r != 0) return;
      out.grains = all.size(), out.pairs = saved.pairs.size(), out.spars = saved.spars.size();
      out.clumps = clumps.size(), out.clump_ghosts = clumps.ghosts;
      std::swap(w.particles, all);
      std::swap(w.clumps, clumps);
      NeighbourList<D> none;
      w.nlist.swap_rows(none);
      w.broken_bonds = broken;
      StateWriter world_out, domain_out;
      save_world_state(world_out, w);
      saved.visit(domain_out);
      out.world = world_out.bytes(), out.domain = domain_out.bytes();
    });
  for (auto& t : threads) t.join();
  return out;
}

// The checkpoint resumed on `ranks` ranks: each makes the world, loads the saved state, takes
// its slab as the saved domain says and goes on (run(world)); returns the ranks' worlds.
template <int D, class Make, class Run>
std::vector<World<D>> resume_on_ranks(int ranks, const SavedDomain& saved, Make&& make, Run&& run) {
  Hub hub(ranks);
  std::vector<World<D>> parts(static_cast<std::size_t>(ranks));
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      auto& w = parts[static_cast<std::size_t>(r)];
      w = make();
      StateReader world_in(saved.world.data(), saved.world.size());
      load_world_state(world_in, w);
      DomainCheckpoint<D> domain;
      StateReader domain_in(saved.domain.data(), saved.domain.size());
      domain.visit(domain_in);
      SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r), &domain);
      run(w);
    });
  for (auto& t : threads) t.join();
  return parts;
}

}  // namespace geodem::test
