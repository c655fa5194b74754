// A periodic cell decomposed over ranks (domain/slab_domain.hpp): slabs along the cell's first
// fractional coordinate that close in a ring, the first and last ranks neighbours across the
// faces. The ranks are threads (domain_ranks.hpp); tests/mpi/test_cell_ranks.py runs the
// simple shear and periodic triaxial kinds across processes.
#include <gtest/gtest.h>

#include <thread>

#include "base/error.hpp"
#include "controllers/cell_servo.hpp"
#include "domain_ranks.hpp"
#include "moving_worlds.hpp"

namespace geodem::test {
namespace {

template <typename T>
class DomainPeriodicTest : public ::testing::Test {};
TYPED_TEST_SUITE(DomainPeriodicTest, Dims, DimNames);

// The sheared cell of colliding grains (moving_worlds.hpp): 900 discs or 1,000 spheres, keys
// by id and one force slab (the bits of one process) unless `cell_order`.
template <int D>
World<D> cell(bool cell_order = false, bool servo = false) {
  World<D> w = sheared_cell<D>(D == 2 ? 30 : 10);
  w.sort_interval = cell_order ? 3 : 0;
  w.one_slab = !cell_order;
  if (servo) {  // the cell's size follows its stress: its sums must agree on every rank
    using Axis = typename CellServo<D>::Axis;
    std::array<Axis, D> axes;
    for (auto& a : axes) a = Axis{true, 2e4, 0.0};
    w.controllers.push_back(std::make_shared<CellServo<D>>(axes, 5.0, 0.1));
  }
  return w;
}

constexpr int kSteps = 400;

template <int D>
void advance(World<D>& w, int from = 0, int to = kSteps) {
  for (int k = from; k < to; ++k) step(w);
}

// What every rank ends with: its world, the grains it sent away, and its ghosts that came
// across the cell's faces (from the last rank to the first, or back).
template <int D>
struct Ranks {
  std::vector<World<D>> worlds;
  std::uint64_t migrated = 0;
  std::size_t ghosts_across_faces = 0;
};

template <int D>
Ranks<D> on_ranks(int ranks, bool cell_order, bool servo) {
  Hub hub(ranks);
  Ranks<D> out;
  out.worlds.resize(static_cast<std::size_t>(ranks));
  std::vector<std::uint64_t> migrated(out.worlds.size(), 0);
  std::vector<std::size_t> across(out.worlds.size(), 0);
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      auto& w = out.worlds[static_cast<std::size_t>(r)];
      w = cell<D>(cell_order, servo);
      auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
      // The cuts stay where distributed: the crossings asserted below happen at them (moved by
      // measured times, they may fall where no grain crosses; domain_test.cpp moves them).
      d->rebalance_every = 0;
      advance(w);
      migrated[static_cast<std::size_t>(r)] = d->migrated();
      // On the first rank, a ghost in the far half of the cell came through its lower face.
      const auto h_inv = w.cell.h.inverse().eval();
      const auto& P = w.particles;
      for (std::size_t i = 0; i < P.size() && r == 0 && ranks > 1; ++i)
        if ((P.flags[i] & kGhost) && (h_inv * P.pos[i]).x() > 0.5)
          ++across[static_cast<std::size_t>(r)];
    });
  for (auto& t : threads) t.join();
  for (auto m : migrated) out.migrated += m;
  for (auto a : across) out.ghosts_across_faces += a;
  return out;
}

template <int D>
std::vector<Grain<D>> owned_by_id(const std::vector<World<D>>& parts) {
  std::size_t n = 0, ghosts = 0;
  for (const auto& w : parts) n += w.particles.size();
  n -= ghosts_in(parts);
  return by_id(parts, n, ghosts);
}

// Keys by id and one force slab: 2 and 3 ranks end in the bits of one process, grains that
// crossed the faces and the cuts included; the cell's sums (the symmetric part of d f^T and
// the stiffness, summed exactly over the ranks) are the same on every rank and within 1e-12
// of the one process's.
TYPED_TEST(DomainPeriodicTest, AShearedCellOnRanksGivesTheBitsOfOneProcess) {
  constexpr int D = TypeParam::value;
  World<D> one = cell<D>();
  advance(one);
  std::vector<World<D>> alone(1);
  alone[0] = one;
  const auto reference = owned_by_id(alone);
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(::testing::Message() << ranks << " ranks");
    const auto run = on_ranks<D>(ranks, false, false);
    expect_same<D>(owned_by_id(run.worlds), reference);
    EXPECT_GT(run.migrated, 0u) << "no grain changed rank";
    EXPECT_GT(run.ghosts_across_faces, 0u) << "no ghost came across the cell's faces";
    // (the ranks sum the symmetric part, the stress's: one process the whole tensor)
    const auto& f0 = run.worlds[0].cell_fabric;
    const auto sym = (0.5 * (one.cell_fabric + one.cell_fabric.transpose())).eval();
    const double scale = sym.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0.0);
    EXPECT_LE((f0 - sym).cwiseAbs().maxCoeff(), 1e-12 * scale);
    EXPECT_TRUE(f0 == f0.transpose());
    EXPECT_LE((run.worlds[0].cell_stiffness - one.cell_stiffness).cwiseAbs().maxCoeff(),
              1e-12 * one.cell_stiffness.cwiseAbs().maxCoeff());
    for (const auto& w : run.worlds) {
      EXPECT_TRUE(w.cell_fabric == f0);
      EXPECT_TRUE(w.cell_stiffness == run.worlds[0].cell_stiffness);
      EXPECT_TRUE(w.cell.h == one.cell.h);
    }
  }
}

// The cell's size driven by a stress servo from the exactly summed stress, grains in cell
// order every 3 builds: 1, 2 and 3 ranks end in the same bits, grains and cell.
TYPED_TEST(DomainPeriodicTest, AServoDrivenCellKeepsItsBitsOnAnyRankCount) {
  constexpr int D = TypeParam::value;
  const auto one = on_ranks<D>(1, true, true);
  const auto reference = owned_by_id(one.worlds);
  EXPECT_FALSE(one.worlds[0].cell.h == cell<D>().cell.h) << "the servo did not move the cell";
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(::testing::Message() << ranks << " ranks");
    const auto run = on_ranks<D>(ranks, true, true);
    expect_same<D>(owned_by_id(run.worlds), reference);
    EXPECT_GT(run.migrated, 0u);
    for (const auto& w : run.worlds) {
      EXPECT_TRUE(w.cell.h == one.worlds[0].cell.h);
      EXPECT_TRUE(w.cell_fabric == one.worlds[0].cell_fabric);
    }
  }
}

// A checkpoint of a sheared cell on 3 ranks (the cell's shape at the last build kept with it)
// resumed on 2 and on 1 goes on with the bits of the uninterrupted run.
TYPED_TEST(DomainPeriodicTest, ACheckpointResumesOnOtherRankCounts) {
  constexpr int D = TypeParam::value;
  constexpr int kCut = 170;
  const auto uninterrupted = on_ranks<D>(3, true, false);
  const auto reference = owned_by_id(uninterrupted.worlds);
  const SavedDomain saved = checkpoint_on_ranks<D>(
      3, [] { return cell<D>(true); }, [](World<D>& w) { advance(w, 0, kCut); });
  EXPECT_GT(saved.pairs, 0u);
  for (int ranks : {2, 1}) {
    SCOPED_TRACE(::testing::Message() << "resumed on " << ranks << " ranks");
    const auto parts = resume_on_ranks<D>(
        ranks, saved, [] { return cell<D>(true); }, [](World<D>& w) { advance(w, kCut, kSteps); });
    expect_same<D>(owned_by_id(parts), reference);
    for (const auto& w : parts) EXPECT_TRUE(w.cell.h == uninterrupted.worlds[0].cell.h);
  }
}

// Slabs thinner than the ghost width are refused, naming the cause.
TYPED_TEST(DomainPeriodicTest, TooManyRanksForTheCellAreRefused) {
  constexpr int D = TypeParam::value;
  constexpr int kRanks = D == 2 ? 32 : 12;
  Hub hub(kRanks);
  std::vector<std::string> errors(kRanks);
  std::vector<std::thread> threads;
  for (int r = 0; r < kRanks; ++r)
    threads.emplace_back([&, r] {
      World<D> w = cell<D>();
      try {
        SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
      } catch (const InputError& e) {
        errors[static_cast<std::size_t>(r)] = e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (const auto& e : errors) EXPECT_NE(e.find("too thin"), std::string::npos) << e;
}

}  // namespace
}  // namespace geodem::test
