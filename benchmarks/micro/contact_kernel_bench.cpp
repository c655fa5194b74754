// The grain-grain force stage per contact (ns/contact) on each path (contacts/contact_batch.hpp:
// the scalar loop, the SSE2, AVX2 and AVX-512 batches), for the linear and the Hertz-Mindlin
// laws, in 2D and 3D, on one thread. The packing: 20,000 grains on a lattice whose spacing
// (1.98 r) is below the mean diameter, radii spread by +-3 % so that some listed pairs are
// apart, random velocities and spins so that springs load and some contacts slide, no walls.
// Arguments: law (0 linear, 1 Hertz), path (0 scalar, 1 sse2, 2 avx2, 3 avx512). A path the
// processor lacks is skipped.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "broadphase/neighbour_search.hpp"
#include "contacts/contact_batch.hpp"
#include "contacts/contact_forces.hpp"

namespace {

constexpr std::size_t kGrains = 20000;

template <int D>
geodem::World<D> jittered_lattice(bool hertz) {
  geodem::World<D> w;
  geodem::Material m;
  m.law = hertz ? geodem::LawKind::kHertz : geodem::LawKind::kLinear;
  m.kn = 1e5;
  m.young = 1e8;
  m.poisson = 0.3;
  m.friction = 0.5;
  m.restitution = 0.5;
  m.tangential_damping = true;
  w.materials = {m};
  w.resolve_pair_laws();
  const double r = 0.01, spacing = 1.98 * r;
  const int side = static_cast<int>(std::ceil(std::pow(static_cast<double>(kGrains), 1.0 / D)));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b)
      for (int c = 0; c < (D == 3 ? side : 1); ++c) {
        typename geodem::Dim<D>::Vec x;
        x[0] = a * spacing, x[1] = b * spacing;
        if constexpr (D == 3) x[2] = c * spacing;
        const auto i = w.particles.add(x, r * (1.0 + 0.03 * u(rng)), 2500.0, 0);
        for (int k = 0; k < D; ++k) w.particles.vel[i][k] = 0.1 * u(rng);
        if constexpr (D == 3) {
          for (int k = 0; k < 3; ++k) w.particles.angvel[i][k] = 10.0 * u(rng);
        } else {
          w.particles.angvel[i] = 10.0 * u(rng);
        }
      }
  w.dt = 1e-6;
  w.sort_interval = 1;
  geodem::build_neighbour_list(w);
  return w;
}

template <int D>
void BM_ContactForcePerContact(benchmark::State& state) {
  const auto path = static_cast<geodem::ContactPath>(state.range(1));
  if (!geodem::set_contact_path(path)) {
    state.SkipWithError("path not supported by this processor");
    return;
  }
  auto w = jittered_lattice<D>(state.range(0) == 1);
  w.measure_this_step = true;  // counts the contacts
  geodem::compute_contact_forces(w);
  const auto contacts = static_cast<std::int64_t>(w.stats.contacts);
  w.measure_this_step = false;
  for (auto _ : state) geodem::compute_contact_forces(w);
  state.SetItemsProcessed(state.iterations() * contacts);
  state.counters["ns_per_contact"] = benchmark::Counter(
      static_cast<double>(contacts) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["contacts"] = static_cast<double>(contacts);
  state.counters["listed"] = static_cast<double>(w.nlist.pair_count());
  state.SetLabel(geodem::contact_path_name(path));
  geodem::set_contact_path(geodem::default_contact_path());
}

}  // namespace

BENCHMARK(BM_ContactForcePerContact<3>)
    ->ArgsProduct({{0, 1}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ContactForcePerContact<2>)
    ->ArgsProduct({{0, 1}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
