// Cost of clumps against round grains with the same number of member spheres/discs:
// a dense lattice packing (every grain overlaps its lattice neighbours by 1 %), once
// as N round grains and once as N/2 rigid pairs (neighbouring lattice sites joined).
// The whole step is timed; items are member grains, so the rates compare directly. The
// second argument is the thread count.
#include <benchmark/benchmark.h>

#include <cmath>

#include "broadphase/neighbour_search.hpp"
#include "clumps/clump_dynamics.hpp"
#include "integrate/integrator.hpp"
#include "world/step.hpp"

namespace {

template <int D>
geodem::World<D> packing(std::size_t n_target, bool clumps, int threads) {
  using Vec = typename geodem::Dim<D>::Vec;
  geodem::World<D> w;
  geodem::Material m;
  m.kn = 1e5;
  m.friction = 0.5;
  w.materials = {m};
  w.resolve_pair_laws();
  const double r = 0.01, spacing = 1.98 * r;
  int side = static_cast<int>(std::ceil(std::pow(static_cast<double>(n_target), 1.0 / D)));
  side += side % 2;  // pairs along x
  geodem::ClumpTemplate<D> t;
  t.centre = {Vec::Zero(), Vec(spacing * Vec::Unit(0))};
  t.radius = {r, r};
  const auto pair = geodem::resolve_clump(t);
  for (int a = 0; a < side; a += clumps ? 2 : 1)
    for (int b = 0; b < side; ++b)
      for (int c = 0; c < (D == 3 ? side : 1); ++c) {
        Vec x;
        x[0] = a * spacing, x[1] = b * spacing;
        if constexpr (D == 3) x[2] = c * spacing;
        if (clumps) {
          geodem::add_clump(w, pair, Vec(x + 0.5 * spacing * Vec::Unit(0)),
                            geodem::Dim<D>::identity(), 1.0, 2500.0, 0);
        } else {
          w.particles.add(x, r, 2500.0, 0);
        }
      }
  w.dt = 1e-6;
  w.local_damping = 0.2;
  w.sort_interval = 1;
  w.threads = threads;
  geodem::build_neighbour_list(w);
  return w;
}

template <int D>
void BM_StepRound(benchmark::State& state) {
  auto w =
      packing<D>(static_cast<std::size_t>(state.range(0)), false, static_cast<int>(state.range(1)));
  for (auto _ : state) geodem::step(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

template <int D>
void BM_StepClumpPairs(benchmark::State& state) {
  auto w =
      packing<D>(static_cast<std::size_t>(state.range(0)), true, static_cast<int>(state.range(1)));
  for (auto _ : state) geodem::step(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

// The integration stage alone (clumps: members summed, rigid-body step, members placed).
template <int D>
void BM_IntegrateRound(benchmark::State& state) {
  auto w =
      packing<D>(static_cast<std::size_t>(state.range(0)), false, static_cast<int>(state.range(1)));
  for (auto _ : state) geodem::integrate(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

template <int D>
void BM_IntegrateClumpPairs(benchmark::State& state) {
  auto w =
      packing<D>(static_cast<std::size_t>(state.range(0)), true, static_cast<int>(state.range(1)));
  for (auto _ : state) geodem::integrate(w);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.particles.size()));
}

}  // namespace

BENCHMARK(BM_IntegrateRound<3>)->Args({20000, 1})->Args({20000, 2})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IntegrateClumpPairs<3>)
    ->Args({20000, 1})
    ->Args({20000, 2})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepRound<2>)->Args({20000, 1})->Args({20000, 2})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepClumpPairs<2>)->Args({20000, 1})->Args({20000, 2})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepRound<3>)->Args({20000, 1})->Args({20000, 2})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepClumpPairs<3>)->Args({20000, 1})->Args({20000, 2})->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
