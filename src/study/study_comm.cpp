#include "study/study_comm.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "study/group_comm.hpp"

namespace geodem::comm {

namespace {
bool g_active = false;
int g_rank = 0, g_size = 1;
int g_group_size = 1;  // ranks per group of a study's runs
#ifdef GEODEM_HAVE_MPI
MPI_Comm g_group = MPI_COMM_NULL;  // (MPI_COMM_WORLD until a split)
#endif

// Whether an MPI launcher (Open MPI, MPICH/Hydra) started the process, with -n 1 too: a scene
// is then decomposed over the ranks, and one rank must give the bits of several.
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}
}  // namespace

void init(int* argc, char*** argv) {
  if (!launched_by_mpi()) return;
#ifdef GEODEM_HAVE_MPI
  int provided = 0;
  // Only the main thread calls MPI; the run workers are threads of their own.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_active = true;
#else
  (void)argc;
  (void)argv;
  throw std::runtime_error(
      "launched by an MPI launcher, but this geodem was built without MPI (install "
      "libopenmpi-dev and rebuild); run it without mpirun");
#endif
}

void finalize() {
#ifdef GEODEM_HAVE_MPI
  if (g_group != MPI_COMM_NULL) MPI_Comm_free(&g_group);
  if (g_active) MPI_Finalize();
#endif
  g_active = false;
}

int abort_all(int code) {
#ifdef GEODEM_HAVE_MPI
  if (g_active) {
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
  }
#endif
  return code;
}

bool active() {
  return g_active;
}

bool built_with_mpi() {
#ifdef GEODEM_HAVE_MPI
  return true;
#else
  return false;
#endif
}
int rank() {
  return g_rank;
}
int size() {
  return g_size;
}

std::vector<std::string> all_gather(const std::string& mine) {
  if (!g_active) return {mine};
#ifdef GEODEM_HAVE_MPI
  int len = static_cast<int>(mine.size());
  std::vector<int> lens(static_cast<std::size_t>(g_size)), offsets(lens.size());
  MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (std::size_t r = 0; r < lens.size(); ++r) {
    offsets[r] = total;
    total += lens[r];
  }
  std::string all(static_cast<std::size_t>(total), '\0');
  MPI_Allgatherv(mine.data(), len, MPI_CHAR, all.data(), lens.data(), offsets.data(), MPI_CHAR,
                 MPI_COMM_WORLD);
  std::vector<std::string> parts;
  for (std::size_t r = 0; r < lens.size(); ++r)
    parts.push_back(
        all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(lens[r])));
  return parts;
#else
  return {mine};
#endif
}

void split_into_groups(int ranks_per_group) {
  if (ranks_per_group < 1 || g_size % ranks_per_group != 0)
    throw std::runtime_error("ranks per group must divide the ranks");
  g_group_size = ranks_per_group;
#ifdef GEODEM_HAVE_MPI
  if (g_active && ranks_per_group > 1)
    MPI_Comm_split(MPI_COMM_WORLD, g_rank / ranks_per_group, g_rank, &g_group);
#endif
}
int group() {
  return g_rank / g_group_size;
}
int groups() {
  return g_size / g_group_size;
}
int group_rank() {
  return g_rank % g_group_size;
}
int group_size() {
  return g_group_size;
}

bool group_all(bool mine) {
#ifdef GEODEM_HAVE_MPI
  if (g_active) {
    int all = mine ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_LAND, group_communicator());
    return all != 0;
  }
#endif
  return mine;
}

#ifdef GEODEM_HAVE_MPI
MPI_Comm group_communicator() {
  return g_group != MPI_COMM_NULL ? g_group : MPI_COMM_WORLD;
}
#endif

}  // namespace geodem::comm
