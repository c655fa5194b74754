// Times a scene's steps on one process or decomposed over the ranks of mpirun
// (domain/slab_domain.hpp), and measures what crosses between ranks: B6 in
// benchmarks/README.md, the cost model of docs/parallel.md.
//
//   geodem_domain_bench SCENARIO.toml STEPS serial|domain [REBALANCE_EVERY]
//
// The scene is built as `geodem run` builds it, stepped once (the first list build, and the
// distribution), then STEPS steps are timed between barriers. Each rank prints its grains,
// ghosts, the bytes of its last ghost update, the seconds it spent in messages and its
// resident memory at the end and at its peak; rank 0 prints the whole run's rate.
#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "base/parallel.hpp"
#include "distributed/mpi_domain_comm.hpp"
#include "domain/slab_domain.hpp"
#include "io/toml_reader.hpp"
#include "scene/build_scene.hpp"
#include "scene/scene_settings.hpp"
#include "scene/scene_start.hpp"
#include "world/step.hpp"

namespace geodem {
namespace {

using Clock = std::chrono::steady_clock;

// Counts the time spent in another comm's calls.
class TimedComm final : public DomainComm {
 public:
  explicit TimedComm(std::shared_ptr<DomainComm> c) : c_(std::move(c)) {}
  int rank() const override { return c_->rank(); }
  int size() const override { return c_->size(); }
  void exchange(const Bytes& a, const Bytes& b, Bytes& x, Bytes& y) override {
    const auto t = Clock::now();
    c_->exchange(a, b, x, y);
    seconds += std::chrono::duration<double>(Clock::now() - t).count();
  }
  double max(double v) override {
    return timed([&] { return c_->max(v); });
  }
  double min(double v) override {
    return timed([&] { return c_->min(v); });
  }
  void sum(std::vector<ExactSum>& s) override {
    timed([&] {
      c_->sum(s);
      return 0.0;
    });
  }
  Bytes all_gather(const Bytes& b) override { return c_->all_gather(b); }
  Bytes gather(const Bytes& b) override { return c_->gather(b); }
  double seconds = 0.0;

 private:
  template <typename F>
  double timed(F&& f) {
    const auto t = Clock::now();
    const double v = f();
    seconds += std::chrono::duration<double>(Clock::now() - t).count();
    return v;
  }
  std::shared_ptr<DomainComm> c_;
};

// Resident memory now (VmRSS) or at its peak (VmHWM), kB, from /proc/self/status.
long status_kb(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(field.size()));
  return -1;
}

template <int D>
int run(const SceneSettings& s, long steps, bool domain, int rebalance_every) {
  World<D> w;
  build_world<D>(s, w);
  if (!s.start_checkpoint.empty()) start_from_checkpoint(s, w);
  w.threads = default_threads();  // GEODEM_THREADS, else OMP_NUM_THREADS, else 1
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::shared_ptr<TimedComm> comm;
  std::shared_ptr<SlabDomain<D>> d;
  if (domain) {
    comm = std::make_shared<TimedComm>(mpi_domain_comm());
    d = SlabDomain<D>::distribute(w, comm);
    if (rebalance_every >= 0) d->rebalance_every = rebalance_every;  // else the domain's default
  }
  if (w.dt <= 0.0) update_timestep(w);
  w.measure_this_step = false;  // the runners measure on their record steps only
  step(w);
  if (comm) comm->seconds = 0.0;
  const std::uint64_t builds0 = w.nlist.builds;
  const std::vector<double> cuts0 = d ? d->cuts() : std::vector<double>{};
  MPI_Barrier(MPI_COMM_WORLD);
  const auto t0 = Clock::now();
  for (long k = 0; k < steps; ++k) step(w);
  MPI_Barrier(MPI_COMM_WORLD);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const std::size_t owned = d ? d->owned(w) : w.particles.size();
  long total = static_cast<long>(owned);
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  const long rss = status_kb("VmRSS:"), peak = status_kb("VmHWM:");
  std::printf(
      "rank %d/%d: %zu grains, %zu ghosts, ghost update %zu bytes/step, messages %.3f s of "
      "%.3f s, %llu builds, resident %ld kB, peak %ld kB (%.0f bytes per grain)\n",
      rank, ranks, owned, w.particles.size() - owned, d ? d->halo_bytes() : 0,
      comm ? comm->seconds : 0.0, seconds,
      static_cast<unsigned long long>(w.nlist.builds - builds0), rss, peak,
      1024.0 * static_cast<double>(peak) / static_cast<double>(owned));
  std::fflush(stdout);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0 && d)
    std::printf(
        "cuts moved: %s; modelled work of the busiest rank at the last window: %.3f of "
        "an even share\n",
        d->cuts() == cuts0 ? "no" : "yes", d->work_imbalance());
  if (rank == 0) {
    std::printf("rank 0 stages (s, whole run):");
    for (int k = 0; k < static_cast<int>(Stage::kCount); ++k)
      std::printf(" %s %.3f", stage_name(static_cast<Stage>(k)), w.stage_seconds[k]);
    std::printf("\n");
  }
  if (rank == 0)
    std::printf(
        "%s, %d rank(s) of %d thread(s): %ld grains, %ld steps in %.3f s: %.3f M "
        "particle-steps/s\n",
        domain ? "domain" : "one process", ranks, w.threads, total, steps, seconds,
        static_cast<double>(total) * static_cast<double>(steps) / seconds * 1e-6);
  return 0;
}

}  // namespace
}  // namespace geodem

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::fprintf(
        stderr, "usage: geodem_domain_bench SCENARIO.toml STEPS serial|domain [REBALANCE_EVERY]\n");
    return 2;
  }
  MPI_Init(&argc, &argv);
  int rc = 1;
  try {
    const toml::table root = geodem::parse_toml_file(argv[1]);
    const geodem::SceneSettings s = geodem::read_scene(root, argv[1]);
    const long steps = std::atol(argv[2]);
    const bool domain = std::strcmp(argv[3], "domain") == 0;
    const int rebalance = argc == 5 ? std::atoi(argv[4]) : -1;
    rc = s.dimension == 2 ? geodem::run<2>(s, steps, domain, rebalance)
                          : geodem::run<3>(s, steps, domain, rebalance);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "geodem_domain_bench: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return rc;
}
