// The Verlet list against brute force on random clouds: every grain pair closer than
// r_i + r_j + skin and every grain-wall pair closer than r + skin is listed, and nothing
// else; rows are sorted and hold each pair once; history is carried over by a rebuild, by
// the removal of grains (excavation) and by the removal of a wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>

#include "broadphase/list_history.hpp"
#include "broadphase/neighbour_search.hpp"
#include "test_util.hpp"
#include "world/world_editing.hpp"

namespace geodem::test {
namespace {

template <typename T>
class NeighbourListTest : public ::testing::Test {};
TYPED_TEST_SUITE(NeighbourListTest, Dims, DimNames);

enum class Cloud { kUniform, kClustered, kWithOutlier };

// Random grains (radii 0.5 to 1.5) in a box of side L, with plane walls on the box faces.
template <int D>
World<D> random_cloud(Cloud kind, std::size_t n, double side, std::uint64_t seed) {
  World<D> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 0.5));
  add_box(w, Vec<D>(Vec<D>::Zero()), Vec<D>(Vec<D>::Constant(side)), mat, mat);
  if constexpr (D == 2) {
    Wall<D> seg;  // a slanted segment across the box
    seg.kind = WallKind::kSegment;
    seg.point = vec<D>(0.2 * side, 0.3 * side);
    seg.end = vec<D>(0.7 * side, 0.6 * side);
    seg.material = mat;
    w.walls.push_back(seg);
  }
  w.resolve_pair_laws();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> x;
    for (int k = 0; k < D; ++k) {
      x[k] = kind == Cloud::kClustered ? 0.5 * side + 0.08 * side * gauss(rng) : side * u(rng);
    }
    w.particles.add(x, 0.5 + u(rng), 1000.0, mat);
  }
  if (kind == Cloud::kWithOutlier) {
    // One grain very far away: the grid must coarsen and clamp, not lose neighbours.
    w.particles.add(Vec<D>(Vec<D>::Constant(1e4 * side)), 1.0, 1000.0, mat);
    w.particles.add(Vec<D>(Vec<D>::Constant(1e4 * side + 1.5)), 1.0, 1000.0, mat);
  }
  return w;
}

// Whether the list's test lists a pair: |xj - xi| < (ri + skin) + rj, as the search does.
template <int D>
bool within_reach(const World<D>& w, std::size_t i, std::size_t j, double skin) {
  const auto& P = w.particles;
  const double reach = P.radius[i] + skin + P.radius[j];
  return (P.pos[j] - P.pos[i]).squaredNorm() < reach * reach;
}

template <int D>
double wall_gap(const Wall<D>& wall, const Vec<D>& x) {
  if (wall.kind == WallKind::kPlane) return (x - wall.point).dot(wall.normal);
  const Vec<D> seg = wall.end - wall.point;
  const double t = std::clamp((x - wall.point).dot(seg) / seg.squaredNorm(), 0.0, 1.0);
  return (wall.point + t * seg - x).norm();
}

template <int D>
void check_against_brute_force(const World<D>& w) {
  const auto& P = w.particles;
  const auto& L = w.nlist;
  const std::size_t n = P.size();
  ASSERT_EQ(L.start.size(), n + 1);
  ASSERT_EQ(L.wall_start.size(), n + 1);
  ASSERT_EQ(L.spring.size(), L.other.size());
  ASSERT_EQ(L.wall_spring.size(), L.wall.size());
  std::set<std::pair<std::size_t, std::size_t>> listed;
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_LE(L.start[i], L.start[i + 1]);
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::size_t j = L.other[k];
      ASSERT_GT(j, i) << "a pair belongs to the row of its lower index";
      ASSERT_LT(j, n);
      if (k > L.start[i]) {
        ASSERT_LT(L.other[k - 1], L.other[k]) << "rows sorted, no repeats";
      }
      EXPECT_TRUE(within_reach(w, i, j, L.skin)) << "listed pair out of reach: " << i << " " << j;
      listed.emplace(i, j);
    }
  }
  std::size_t expected = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (within_reach(w, i, j, L.skin)) {
        ++expected;
        EXPECT_TRUE(listed.count({i, j})) << "pair missing from the list: " << i << " " << j;
      }
  EXPECT_EQ(listed.size(), expected);

  for (std::size_t i = 0; i < n; ++i) {
    std::set<std::size_t> walls;
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) walls.insert(L.wall[k]);
    EXPECT_EQ(walls.size(), L.wall_start[i + 1] - L.wall_start[i]) << "wall listed twice";
    for (std::size_t k = 0; k < w.walls.size(); ++k) {
      const bool near = wall_gap(w.walls[k], P.pos[i]) < P.radius[i] + L.skin;
      EXPECT_EQ(walls.count(k) == 1, near) << "grain " << i << " wall " << k;
    }
  }
}

TYPED_TEST(NeighbourListTest, MatchesBruteForceOnRandomClouds) {
  constexpr int D = TypeParam::value;
  const double side = D == 2 ? 40.0 : 14.0;
  std::uint64_t seed = 1;
  for (Cloud kind : {Cloud::kUniform, Cloud::kClustered, Cloud::kWithOutlier}) {
    for (double skin_factor : {0.1, 0.4, 1.5}) {
      SCOPED_TRACE("cloud " + std::to_string(static_cast<int>(kind)) + ", skin factor " +
                   std::to_string(skin_factor));
      World<D> w = random_cloud<D>(kind, 400, side, ++seed);
      w.skin_factor = skin_factor;
      build_neighbour_list(w);
      EXPECT_NEAR(w.nlist.skin, skin_factor * 1.0, 0.1 * skin_factor);  // mean radius ~ 1
      check_against_brute_force(w);
    }
  }
}

// A tangential spring of length v along the first axis.
template <int D>
TangentSpring<D> spring_of(double v) {
  if constexpr (D == 2) {
    return v;
  } else {
    return Vec<D>(v, 0.0, 0.0);
  }
}

// On threads, each thread lists a run of consecutive rows into a part of its own, copied in
// after the first thread's: the rows, and the history a second build carries over with the
// old rows kept from the first, must be the same on any thread count.
TYPED_TEST(NeighbourListTest, RowsAndHistoryTheSameOnAnyThreadCount) {
  constexpr int D = TypeParam::value;
  const std::size_t n = 2 * kParallelMin + 77;  // enough for the build to take threads
  const double side = D == 2 ? 120.0 : 24.0;
  World<D> reference;
  for (int threads : {1, 2, 3, 5}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    World<D> w = random_cloud<D>(Cloud::kUniform, n, side, 42);
    w.threads = threads;
    w.skin_factor = 0.3;
    build_neighbour_list(w);
    // A history on every third pair and wall entry, then every grain nudged and rebuilt.
    for (std::size_t k = 0; k < w.nlist.spring.size(); k += 3)
      w.nlist.spring[k] = spring_of<D>(1e-3 * double(k + 1));
    for (std::size_t k = 0; k < w.nlist.wall_spring.size(); k += 3)
      w.nlist.wall_spring[k] = spring_of<D>(-1e-3 * double(k + 1));
    for (std::size_t i = 0; i < n; ++i) w.particles.pos[i][0] += 0.05 * std::sin(double(i));
    build_neighbour_list(w);
    check_against_brute_force(w);
    EXPECT_TRUE(w.keep_build_scratch) << "a small build's scratch stays mapped";
    if (threads == 1) {
      reference = w;
      continue;
    }
    const auto& L = w.nlist;
    const auto& R = reference.nlist;
    EXPECT_EQ(L.start, R.start);
    EXPECT_EQ(L.other, R.other);
    EXPECT_EQ(L.wall_start, R.wall_start);
    EXPECT_EQ(L.wall, R.wall);
    ASSERT_EQ(L.spring.size(), R.spring.size());
    for (std::size_t k = 0; k < L.spring.size(); ++k)
      ASSERT_EQ(L.spring[k], R.spring[k]) << "pair entry " << k;
    ASSERT_EQ(L.wall_spring.size(), R.wall_spring.size());
    for (std::size_t k = 0; k < L.wall_spring.size(); ++k)
      ASSERT_EQ(L.wall_spring[k], R.wall_spring[k]) << "wall entry " << k;
  }
}

// A build whose scratch (the force arrays alone, here) weighs more than kSmallBuildScratch
// gives it back: the old rows' copy and the threads' parts are freed when the build ends.
TYPED_TEST(NeighbourListTest, LargeBuildsGiveTheirScratchBack) {
  constexpr int D = TypeParam::value;
  const std::size_t n =
      kSmallBuildScratch / (sizeof(typename Dim<D>::Vec) + sizeof(typename Dim<D>::Rot)) + 1;
  World<D> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 0.5));
  w.resolve_pair_laws();
  w.threads = 2;
  // A simple cubic lattice of touching unit spheres: every grain has a history to carry.
  const auto per_row = static_cast<std::size_t>(std::ceil(std::pow(double(n), 1.0 / D)));
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> x;
    std::size_t rest = i;
    for (int k = 0; k < D; ++k, rest /= per_row) x[k] = 1.99 * double(rest % per_row);
    w.particles.add(x, 1.0, 1000.0, mat);
  }
  build_neighbour_list(w);
  for (auto& s : w.nlist.spring) s = spring_of<D>(1e-6);
  build_neighbour_list(w);
  EXPECT_FALSE(w.keep_build_scratch);
  EXPECT_EQ(w.old_rows.bytes(), 0u) << "the old rows' copy is freed";
  EXPECT_TRUE(w.list_parts.empty());
  EXPECT_GT(w.nlist.other.size(), n / 2) << "the lattice's neighbours are listed";
}

// The Verlet guarantee: after every grain moved less than half the skin, each pair now in
// contact was listed at the last build.
TYPED_TEST(NeighbourListTest, ContactsStayListedWithinHalfTheSkin) {
  constexpr int D = TypeParam::value;
  World<D> w = random_cloud<D>(Cloud::kUniform, 500, D == 2 ? 35.0 : 12.0, 99);
  build_neighbour_list(w);
  const auto& L = w.nlist;
  std::set<std::pair<std::size_t, std::size_t>> listed;
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) listed.emplace(i, L.other[k]);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (auto& x : w.particles.pos) {
    Vec<D> d;
    for (int k = 0; k < D; ++k) d[k] = gauss(rng);
    x += 0.4999 * L.skin * d.normalized();
  }
  std::size_t contacts = 0;
  const auto& P = w.particles;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::size_t j = i + 1; j < P.size(); ++j)
      if ((P.pos[j] - P.pos[i]).norm() < P.radius[i] + P.radius[j]) {
        ++contacts;
        EXPECT_TRUE(listed.count({i, j})) << i << " " << j;
      }
  EXPECT_GT(contacts, 50u);
}

// A rebuild keeps the spring of every pair that stays listed and starts new pairs at zero.
TYPED_TEST(NeighbourListTest, RebuildCarriesHistory) {
  constexpr int D = TypeParam::value;
  World<D> w = random_cloud<D>(Cloud::kUniform, 400, D == 2 ? 35.0 : 12.0, 42);
  build_neighbour_list(w);
  auto code = [](std::size_t i, std::size_t j) {
    if constexpr (D == 2) {
      return static_cast<double>(i * 100000 + j);
    } else {
      Vec<D> v = Vec<D>::Constant(static_cast<double>(i));
      v[1] = static_cast<double>(j);
      return v;
    }
  };
  auto& L = w.nlist;
  std::set<std::pair<std::size_t, std::size_t>> before, before_walls;
  for (std::size_t i = 0; i < w.particles.size(); ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      L.spring[k] = code(i, L.other[k]);
      before.emplace(i, L.other[k]);
    }
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      L.wall_spring[k] = code(i, 1000 + L.wall[k]);
      before_walls.emplace(i, L.wall[k]);
    }
  }
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto& x : w.particles.pos)
    for (int k = 0; k < D; ++k) x[k] += 0.5 * u(rng);  // enough for pairs to come and go
  build_neighbour_list(w);
  std::size_t kept = 0, fresh = 0;
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::size_t j = L.other[k];
      if (before.count({i, j})) {
        ++kept;
        EXPECT_EQ(L.spring[k], code(i, j));
      } else {
        ++fresh;
        EXPECT_EQ(L.spring[k], unloaded_spring<D>());
      }
    }
  EXPECT_GT(kept, 100u);
  EXPECT_GT(fresh, 10u);
  std::size_t kept_walls = 0;
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      if (before_walls.count({i, L.wall[k]})) {
        ++kept_walls;
        EXPECT_EQ(L.wall_spring[k], code(i, 1000 + L.wall[k]));
      } else {
        EXPECT_EQ(L.wall_spring[k], unloaded_spring<D>());
      }
    }
  EXPECT_GT(kept_walls, 10u);
}

// Before a build the old rows are cut to the pairs that carry a history: a spring that is not
// +0 bit for bit (-0 is kept), or a bond without a spring. Every row keeps those pairs in
// order, on one thread and on two.
TYPED_TEST(NeighbourListTest, OldRowsKeepThePairsThatCarryAHistory) {
  constexpr int D = TypeParam::value;
  World<D> w = random_cloud<D>(Cloud::kUniform, 6000, D == 2 ? 200.0 : 30.0, 43);
  w.contact_extras = true;
  build_neighbour_list(w);
  auto& L = w.nlist;
  const std::size_t n = w.particles.size();
  ASSERT_GT(L.other.size(), 1000u);
  L.extra.assign(L.other.size(), ContactExtra<D>{});
  auto minus_zero = [] {
    if constexpr (D == 2) {
      return -0.0;
    } else {
      return Vec<D>(-0.0, 0.0, 0.0);
    }
  };
  std::vector<std::vector<std::uint32_t>> expected(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      switch (k % 4) {
        case 0:
          L.spring[k] = unloaded_spring<D>();  // nothing carried
          break;
        case 1:
          L.spring[k] = minus_zero();  // -0: kept
          expected[i].push_back(L.other[k]);
          break;
        case 2:
          L.extra[k].bonded = 1;  // a bond without a spring: kept
          expected[i].push_back(L.other[k]);
          break;
        default:
          if constexpr (D == 2) {
            L.spring[k] = 1.0 + k;
          } else {
            L.spring[k] = Vec<D>(0.0, 1.0 + k, 0.0);
          }
          expected[i].push_back(L.other[k]);
      }
    }
  for (int threads : {1, 2}) {
    NeighbourList<D> list = L, old;
    keep_loaded_pairs(list, old, n, threads);
    ASSERT_EQ(old.start.size(), n + 1);
    for (std::size_t i = 0; i < n; ++i) {
      const std::vector<std::uint32_t> row(old.other.begin() + old.start[i],
                                           old.other.begin() + old.start[i + 1]);
      EXPECT_EQ(row, expected[i]) << "row " << i << ", " << threads << " threads";
    }
    ASSERT_EQ(old.spring.size(), old.other.size());
    ASSERT_EQ(old.extra.size(), old.other.size());
    for (std::size_t k = 0; k < old.other.size(); ++k)
      EXPECT_TRUE(!zero_bits(old.spring[k]) || old.extra[k].bonded) << k;
  }
}

// Grains removed with ContactHistory::kKeep: every pair of two remaining grains keeps its
// spring (labelled here by the grains' ids), pairs with a removed grain are gone, wall
// contacts stay. Then a wall removed: its contacts go, the others keep theirs renumbered.
TYPED_TEST(NeighbourListTest, EditsKeepTheHistoryOfWhatRemains) {
  constexpr int D = TypeParam::value;
  World<D> w = random_cloud<D>(Cloud::kUniform, 400, D == 2 ? 35.0 : 12.0, 7);
  build_neighbour_list(w);
  auto& P = w.particles;
  auto& L = w.nlist;
  auto code = [](double a, double b) {
    if constexpr (D == 2) {
      return a * 100000 + b;
    } else {
      Vec<D> v = Vec<D>::Constant(a);
      v[1] = b;
      return v;
    }
  };
  std::set<std::pair<std::uint64_t, std::uint64_t>> kept_pairs;
  std::set<std::pair<std::uint64_t, std::uint32_t>> wall_pairs;
  for (std::size_t i = 0; i < P.size(); ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const auto a = P.id[i], b = P.id[L.other[k]];
      L.spring[k] = code(double(a), double(b));
      if (a % 3 != 0 && b % 3 != 0) kept_pairs.emplace(a, b);
    }
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      L.wall_spring[k] = code(double(P.id[i]), 1000.0 + L.wall[k]);
      if (P.id[i] % 3 != 0) wall_pairs.emplace(P.id[i], L.wall[k]);
    }
  }
  const auto removed = remove_grains(
      w, grains_where(w, [&](std::size_t i) { return P.id[i] % 3 == 0; }), ContactHistory::kKeep);
  EXPECT_GT(removed, 100u);
  std::set<std::pair<std::uint64_t, std::uint64_t>> after;
  std::set<std::pair<std::uint64_t, std::uint32_t>> after_walls;
  ASSERT_EQ(L.start.size(), P.size() + 1);
  for (std::size_t i = 0; i < P.size(); ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const auto a = P.id[i], b = P.id[L.other[k]];
      EXPECT_LT(i, L.other[k]);
      EXPECT_EQ(L.spring[k], code(double(a), double(b)));
      after.emplace(a, b);
    }
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      EXPECT_EQ(L.wall_spring[k], code(double(P.id[i]), 1000.0 + L.wall[k]));
      after_walls.emplace(P.id[i], L.wall[k]);
    }
  }
  EXPECT_EQ(after, kept_pairs);
  EXPECT_EQ(after_walls, wall_pairs);

  const std::size_t walls_before = w.walls.size();
  remove_wall(w, 1);
  ASSERT_EQ(w.walls.size(), walls_before - 1);
  ASSERT_EQ(w.wall_laws.size(), w.materials.size() * w.walls.size());
  std::size_t still = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      const std::uint32_t old = L.wall[k] >= 1 ? L.wall[k] + 1 : L.wall[k];
      EXPECT_EQ(L.wall_spring[k], code(double(P.id[i]), 1000.0 + old));
      ++still;
    }
  std::size_t expected = 0;
  for (const auto& [id, wall] : wall_pairs) expected += wall != 1 ? 1 : 0;
  EXPECT_EQ(still, expected);
  EXPECT_LT(expected, wall_pairs.size());
}

// Grains appended between builds (a stage's cloud): with empty list rows for them, the next
// build keeps every spring of the grains that were there (labelled by their ids) and lists the
// new grains' pairs unloaded.
TYPED_TEST(NeighbourListTest, AddedGrainsKeepTheHistoryOfTheOthers) {
  constexpr int D = TypeParam::value;
  World<D> w = random_cloud<D>(Cloud::kUniform, 400, D == 2 ? 35.0 : 12.0, 7);
  build_neighbour_list(w);
  auto& P = w.particles;
  auto& L = w.nlist;
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> labelled;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const auto a = std::min(P.id[i], P.id[L.other[k]]), b = std::max(P.id[i], P.id[L.other[k]]);
      const double label = 1.0 + a * 1000.0 + b;
      labelled[{a, b}] = label;
      const double seen = P.id[i] < P.id[L.other[k]] ? label : -label;  // from the row's grain
      if constexpr (D == 2) {
        L.spring[k] = seen;
      } else {
        L.spring[k] = Vec<D>(seen, 0.0, 0.0);
      }
    }
  ASSERT_GT(labelled.size(), 100u);
  const std::size_t before = P.size();
  // Grains beside the cloud, touching each other.
  for (int k = 0; k < 20; ++k) P.add(vec<D>(-10.0 - 1.9 * k, 0.0, 0.0), 1.0, 1000.0, 0);
  add_list_rows_for_new_grains(w, before);
  build_neighbour_list(w);
  std::size_t kept = 0, fresh = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const auto a = std::min(P.id[i], P.id[L.other[k]]), b = std::max(P.id[i], P.id[L.other[k]]);
      if (a >= before) {
        ++fresh;
        EXPECT_EQ(L.spring[k], unloaded_spring<D>());
        continue;
      }
      const auto it = labelled.find({a, b});
      ASSERT_TRUE(it != labelled.end());
      double got;
      if constexpr (D == 2) {
        got = std::abs(L.spring[k]);
      } else {
        got = std::abs(L.spring[k].x());
      }
      EXPECT_EQ(got, it->second) << a << "-" << b;
      kept += got == it->second;
    }
  EXPECT_EQ(kept, labelled.size());
  EXPECT_GE(fresh, 19u);
}

}  // namespace
}  // namespace geodem::test
