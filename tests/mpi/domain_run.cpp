// Runs the pressed packing of the thread-determinism test (tests/pressed_packing.hpp) on one
// process or decomposed over the ranks of mpirun (domain/slab_domain.hpp), and writes every
// grain's final state, sorted by id, as hexadecimal floats: files that compare equal byte for
// byte when the runs gave the same bits (tests/mpi/test_domain.py).
//
//   domain_run DIM EXTRAS STEPS serial|domain|sorted OUT
#include <mpi.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "distributed/mpi_domain_comm.hpp"
#include "domain/slab_domain.hpp"
#include "pressed_packing.hpp"

namespace geodem::test {
namespace {

struct Final {
  std::uint32_t id;
  double v[12];
};

template <int D>
int run(bool extras, int steps, bool domain, bool sorted, const char* out) {
  World<D> w = pressed_packing<D>(extras, 12000, D == 2 ? 100 : 22, 40.0, 11);
  // The one-process reference keeps the grains in id order, in one force slab; "sorted" runs
  // put the ranks' grains in cell order every 3 builds (comparable among themselves).
  if (!sorted) w.sort_interval = 0;
  w.one_slab = true;
  std::shared_ptr<SlabDomain<D>> d;
  if (domain) d = SlabDomain<D>::distribute(w, mpi_domain_comm());
  for (int k = 0; k < steps; ++k) {
    if (k == 100) w.walls[2].velocity = vec<D>(0.0 + 0.05, 0.0, 0.0);  // the floor slides
    step(w);
  }
  const auto& P = w.particles;
  Bytes mine;
  std::vector<Final> rows;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.flags[i] & kGhost) continue;
    Final f{P.id[i], {}};
    int m = 0;
    for (int k = 0; k < D; ++k) f.v[m++] = P.pos[i][k], f.v[m++] = P.vel[i][k];
    if constexpr (D == 2) {
      f.v[m++] = P.angvel[i];
    } else {
      for (int k = 0; k < 3; ++k) f.v[m++] = P.angvel[i][k];
    }
    rows.push_back(f);
  }
  put_records(mine, rows);
  int rank = 0;
  if (domain) {
    rank = d->comm().rank();
    Bytes all = d->comm().all_gather(mine);
    rows.clear();
    std::size_t at = 0;
    while (at < all.size()) append_records(all, at, rows);
    std::printf("rank %d: %zu grains (%zu ghosts), %llu builds, ghost update %zu bytes\n", rank,
                d->owned(w), P.size() - d->owned(w),
                static_cast<unsigned long long>(w.nlist.builds), d->halo_bytes());
  }
  if (rank != 0) return 0;
  std::sort(rows.begin(), rows.end(), [](const Final& a, const Final& b) { return a.id < b.id; });
  FILE* f = std::fopen(out, "w");
  if (!f) return 1;
  std::fprintf(f, "dt %a steps %llu time %a\n", w.dt, static_cast<unsigned long long>(w.step),
               w.time);
  for (const auto& r : rows) {
    std::fprintf(f, "%u", r.id);
    for (int k = 0; k < (D == 2 ? 5 : 9); ++k) std::fprintf(f, " %a", r.v[k]);
    std::fprintf(f, "\n");
  }
  return std::fclose(f) == 0 ? 0 : 1;
}

}  // namespace
}  // namespace geodem::test

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: domain_run DIM EXTRAS STEPS serial|domain|sorted OUT\n");
    return 2;
  }
  MPI_Init(&argc, &argv);
  const int dim = std::atoi(argv[1]), steps = std::atoi(argv[3]);
  const bool extras = std::atoi(argv[2]) != 0, sorted = std::strcmp(argv[4], "sorted") == 0;
  const bool domain = sorted || std::strcmp(argv[4], "domain") == 0;
  int rc = 1;
  try {
    rc = dim == 2 ? geodem::test::run<2>(extras, steps, domain, sorted, argv[5])
                  : geodem::test::run<3>(extras, steps, domain, sorted, argv[5]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "domain_run: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return rc;
}
