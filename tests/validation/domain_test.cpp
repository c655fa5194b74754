// A decomposed domain (domain/slab_domain.hpp) ends in the bits of one process. The ranks here
// are threads that pass their messages through shared memory (ThreadComm), so that the
// migration, ghost and history code runs in the ordinary and the sanitizer builds; the MPI
// transport runs the same comparison across processes (tests/mpi/test_domain.py).
#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <thread>

#include "domain/slab_domain.hpp"
#include "pressed_packing.hpp"

namespace geodem::test {
namespace {

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
    from_lower = rank_ > 0 ? hub_.up[r - 1] : Bytes{};
    from_upper = rank_ + 1 < hub_.size ? hub_.down[r + 1] : Bytes{};
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

template <int D>
World<D> packing(bool extras) {
  World<D> w = pressed_packing<D>(extras, D == 2 ? 6000 : 4000, D == 2 ? 80 : 16, 40.0, 5);
  w.sort_interval = 0;  // the one-process reference keeps id order, in one force slab
  w.one_slab = true;
  return w;
}

constexpr int kSteps = 300;

template <int D>
void advance(World<D>& w) {
  for (int k = 0; k < kSteps; ++k) {
    if (k == 100) w.walls[2].velocity = vec<D>(0.05, 0.0, 0.0);  // the floor slides
    step(w);
  }
}

template <typename T>
class DomainTest : public ::testing::Test {};
TYPED_TEST_SUITE(DomainTest, Dims, DimNames);

TYPED_TEST(DomainTest, ThreeRanksGiveTheBitsOfOneProcess) {
  constexpr int D = TypeParam::value;
  for (bool extras : {false, true}) {
    SCOPED_TRACE(extras ? "rolling springs and bonds" : "frictional");
    World<D> one = packing<D>(extras);
    advance(one);
    constexpr int kRanks = 3;
    Hub hub(kRanks);
    std::vector<World<D>> parts(kRanks);
    std::vector<std::size_t> first_owned(kRanks);
    std::vector<std::thread> threads;
    for (int r = 0; r < kRanks; ++r)
      threads.emplace_back([&, r] {
        auto& w = parts[static_cast<std::size_t>(r)];
        w = packing<D>(extras);
        auto d = SlabDomain<D>::distribute(w, std::make_shared<ThreadComm>(hub, r));
        first_owned[static_cast<std::size_t>(r)] = w.particles.size();
        advance(w);
      });
    for (auto& t : threads) t.join();
    const auto& P1 = one.particles;
    std::size_t owned = 0, ghosts = 0;
    bool moved = false;
    for (int r = 0; r < kRanks; ++r) {
      const auto& w = parts[static_cast<std::size_t>(r)];
      const auto& P = w.particles;
      EXPECT_EQ(w.dt, one.dt);
      for (std::size_t i = 0; i < P.size(); ++i) {
        if (P.flags[i] & kGhost) {
          ++ghosts;
          continue;
        }
        ++owned;
        const std::size_t k = P.id[i];  // the reference keeps id order: index = id
        ASSERT_EQ(P1.id[k], P.id[i]);
        ASSERT_TRUE(P.pos[i] == P1.pos[k]) << "grain " << k << " on rank " << r;
        ASSERT_TRUE(P.vel[i] == P1.vel[k]) << "grain " << k << " on rank " << r;
        ASSERT_TRUE(P.angvel[i] == P1.angvel[k]) << "grain " << k << " on rank " << r;
      }
      const auto now_owned = static_cast<std::size_t>(
          std::count_if(P.flags.begin(), P.flags.end(), [](auto f) { return !(f & kGhost); }));
      moved |= now_owned != first_owned[static_cast<std::size_t>(r)];
    }
    EXPECT_EQ(owned, P1.size());  // every grain owned once
    EXPECT_GT(ghosts, 0u);
    EXPECT_TRUE(moved) << "no grain changed rank: the case does not test migration";
    EXPECT_GE(one.nlist.builds, 4u);
  }
}

}  // namespace
}  // namespace geodem::test
