// Micro-benchmarks of the step's stages on a dense lattice packing (every grain
// touches its lattice neighbours): contact forces, neighbour list rebuild,
// integration, and the whole step, on 1 and 2 threads (arguments: grains, threads).
// Reports grains per second of wall time.
#include <benchmark/benchmark.h>

#include <cmath>

#include "broadphase/neighbour_search.hpp"
#include "contacts/contact_forces.hpp"
#include "integrate/integrator.hpp"
#include "world/step.hpp"

namespace {

template <int D>
geodem::World<D> lattice(std::size_t n_target, std::int64_t threads = 1) {
  geodem::World<D> w;
  w.threads = static_cast<int>(threads);
  geodem::Material m;
  m.kn = 1e5;
  m.friction = 0.5;
  w.materials = {m};
  w.resolve_pair_laws();
  const double r = 0.01, spacing = 1.98 * r;  // 1 % overlap with each lattice neighbour
  const int side = static_cast<int>(std::ceil(std::pow(static_cast<double>(n_target), 1.0 / D)));
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b)
      for (int c = 0; c < (D == 3 ? side : 1); ++c) {
        typename geodem::Dim<D>::Vec x;
        x[0] = a * spacing, x[1] = b * spacing;
        if constexpr (D == 3) x[2] = c * spacing;
        w.particles.add(x, r, 2500.0, 0);
      }
  w.dt = 1e-6;
  w.sort_interval = 1;
  geodem::build_neighbour_list(w);
  return w;
}

template <int D>
void BM_ContactForces(benchmark::State& state) {
  auto w = lattice<D>(static_cast<std::size_t>(state.range(0)), state.range(1));
  for (auto _ : state) geodem::compute_contact_forces(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

template <int D>
void BM_NeighbourBuild(benchmark::State& state) {
  auto w = lattice<D>(static_cast<std::size_t>(state.range(0)), state.range(1));
  for (auto _ : state) geodem::build_neighbour_list(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

template <int D>
void BM_Integrate(benchmark::State& state) {
  auto w = lattice<D>(static_cast<std::size_t>(state.range(0)), state.range(1));
  w.local_damping = 0.2;
  for (auto _ : state) geodem::integrate(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

template <int D>
void BM_Step(benchmark::State& state) {
  auto w = lattice<D>(static_cast<std::size_t>(state.range(0)), state.range(1));
  for (auto _ : state) geodem::step(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

}  // namespace

BENCHMARK(BM_ContactForces<3>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ContactForces<2>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_NeighbourBuild<3>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_NeighbourBuild<2>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Integrate<3>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Integrate<2>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Step<3>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Step<2>)
    ->ArgsProduct({{20000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
