// Determinism you can check: a fixed packing (pressed grains under gravity, rolling and
// twisting friction, bonds that break) run for 600 steps ends in a state whose FNV-1a
// hash over the bits of positions, velocities, spins, ids, contact springs, wall forces
// and the time step equals the one recorded here. Any build (Release, the sanitizers'
// RelWithDebInfo, gcc or clang: -ffp-contract=off keeps a*b+c two roundings everywhere)
// gives these bits; a change of the physics changes them on purpose, and then the hashes
// are re-blessed: run this test, check that the change was meant, and copy the hashes it
// prints into kGolden (docs/verification.md, "Golden state").
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>

#include "pressed_packing.hpp"

namespace geodem::test {
namespace {

constexpr std::uint64_t kGolden2D = 0x131700012196f434ULL;
constexpr std::uint64_t kGolden3D = 0x7506604f0da637a8ULL;

struct Fnv1a {
  std::uint64_t h = 14695981039346656037ULL;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ULL;
  }
  template <class T>
  void all(const std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
};

template <int D>
std::uint64_t state_hash(const World<D>& w) {
  Fnv1a f;
  f.all(w.particles.pos), f.all(w.particles.vel), f.all(w.particles.angvel);
  f.all(w.particles.id), f.all(w.nlist.spring);
  for (const auto& wall : w.walls) f.bytes(wall.force.data(), sizeof(double) * D);
  f.bytes(&w.dt, sizeof w.dt);
  return f.h;
}

template <typename T>
class GoldenState : public ::testing::Test {};
TYPED_TEST_SUITE(GoldenState, Dims, DimNames);

TYPED_TEST(GoldenState, FixedPackingEndsInTheRecordedBits) {
  constexpr int D = TypeParam::value;
  World<D> w = pressed_packing<D>(true, 1500, D == 2 ? 40 : 12, 3.0, 5);
  for (int k = 0; k < 600; ++k) {
    w.measure_this_step = k % 50 == 0;
    step(w);
  }
  ASSERT_GT(w.broken_bonds, 0u);  // the case moves: bonds break, grains fall
  const std::uint64_t got = state_hash(w), want = D == 2 ? kGolden2D : kGolden3D;
  std::printf("[ measured ] %dD state hash 0x%016llxULL\n", D,
              static_cast<unsigned long long>(got));
  EXPECT_EQ(got, want) << D << "D state hash changed: if the physics changed on purpose, "
                       << "record the new hash in kGolden" << D << "D";
}

}  // namespace
}  // namespace geodem::test
