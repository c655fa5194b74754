// The cost of the periodic cell: the same shaken lattice packing (grains 1 % overlapped
// with their lattice neighbours, random velocities that make the neighbour list rebuild
// every few tens of steps) stepped in a box of plane walls and in a periodic cell of the
// lattice's period, where the grains at one face touch the images of those at the other.
// Arguments: grains, periodic (0: walls, 1: cell), shuffled (1: the grains start in random
// memory order, as a generated sample; the first list build renumbers them). One thread.
#include <benchmark/benchmark.h>

#include <cmath>

#include "base/random.hpp"
#include "broadphase/neighbour_search.hpp"
#include "world/step.hpp"

namespace {

template <int D>
geodem::World<D> shaken_lattice(std::size_t n_target, bool periodic, bool shuffled) {
  using Vec = typename geodem::Dim<D>::Vec;
  geodem::World<D> w;
  geodem::Material m;
  m.kn = 1e5;
  m.friction = 0.5;
  w.materials = {m};
  const double r = 0.01, spacing = 1.98 * r;
  const int side = static_cast<int>(std::ceil(std::pow(static_cast<double>(n_target), 1.0 / D)));
  const double period = side * spacing;
  geodem::Random rng(7);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b)
      for (int c = 0; c < (D == 3 ? side : 1); ++c) {
        Vec x;
        x[0] = (a + 0.5) * spacing, x[1] = (b + 0.5) * spacing;
        if constexpr (D == 3) x[2] = (c + 0.5) * spacing;
        w.particles.add(x, r, 2500.0, 0);
        Vec v;
        for (int k = 0; k < D; ++k) v[k] = 0.8 * (rng.uniform() - 0.5);
        w.particles.vel.back() = v;
      }
  if (shuffled) {
    // Grains in random memory order, as a generated sample holds them.
    std::vector<std::uint32_t> order(w.particles.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
    for (std::size_t i = order.size(); i > 1; --i)
      std::swap(order[i - 1],
                order[static_cast<std::size_t>(rng.uniform() * static_cast<double>(i))]);
    w.particles.permute(order);
  }
  if (periodic) {
    w.cell.periodic = true;
    w.cell.h = Vec::Constant(period).asDiagonal();
    w.cell.vel_grad.setZero();
  } else {
    // Plane walls touching the outer grains as the lattice neighbours touch each other.
    for (int k = 0; k < D; ++k)
      for (int side_lo = 0; side_lo < 2; ++side_lo) {
        geodem::Wall<D> wall;
        static const char* names[] = {"x_hi", "x_lo", "y_hi", "y_lo", "z_hi", "z_lo"};
        wall.name = names[2 * k + side_lo];
        wall.normal = Vec::Zero();
        wall.normal[k] = side_lo ? 1.0 : -1.0;
        wall.point = Vec::Zero();
        wall.point[k] = side_lo ? 0.0 : period;
        w.walls.push_back(wall);
      }
  }
  w.resolve_pair_laws();
  w.dt = 1e-4;
  w.sort_interval = 10;
  geodem::build_neighbour_list(w);
  return w;
}

template <int D>
void BM_Step(benchmark::State& state) {
  auto w = shaken_lattice<D>(static_cast<std::size_t>(state.range(0)), state.range(1) != 0,
                             state.range(2) != 0);
  for (int i = 0; i < 200; ++i) geodem::step(w);  // past the first rebuilds
  const auto builds = w.nlist.builds;
  for (auto _ : state) geodem::step(w);
  state.counters["steps_per_build"] =
      static_cast<double>(state.iterations()) /
      static_cast<double>(std::max<std::uint64_t>(1, w.nlist.builds - builds));
  state.counters["listed_pairs"] = static_cast<double>(w.nlist.other.size());
  state.counters["wall_pairs"] = static_cast<double>(w.nlist.wall.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

}  // namespace

BENCHMARK(BM_Step<2>)->ArgsProduct({{20000}, {0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step<3>)->ArgsProduct({{20000}, {0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
