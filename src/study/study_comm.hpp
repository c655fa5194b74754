// The message passing of a study shared across machines: `mpirun -n K geodem run
// study.toml` gives each rank a share of the runs, and the ranks exchange their results
// so that every rank (and the rank-0 report) sees all of them. MPI starts only when the
// process was launched by an MPI launcher; a plain `geodem run` never touches it, and
// builds without MPI refuse to run under one.
#pragma once

#include <string>
#include <vector>

namespace geodem::comm {

// Starts MPI when launched by mpirun/mpiexec (their environment variables say so).
void init(int* argc, char*** argv);
void finalize();
// Ends every rank of mpirun with `code` (an error met by one rank only: the others would wait
// for it in their next message for ever). Returns `code` without MPI.
int abort_all(int code);
bool active();
bool built_with_mpi();
int rank();  // 0 without MPI
int size();  // 1 without MPI
// Every rank passes its part; every rank receives all parts, in rank order.
std::vector<std::string> all_gather(const std::string& mine);

// A study's runs on groups of ranks (`--ranks-per-run R`): the ranks split into size() / R
// groups of R consecutive ranks; each group takes its share of the runs and spreads each run
// over its ranks (docs/parallel.md). Without a split there is one rank a group.
void split_into_groups(int ranks_per_group);  // every rank calls it; size() % R == 0
int group();                                  // this rank's group
int groups();                                 // how many
int group_rank();                             // this rank within its group
int group_size();                             // ranks per group
// Whether `mine` holds on every rank of this rank's group (all of them call it; without MPI,
// `mine`): a decision every rank of a run must take alike, such as loading a file that one rank
// may find and another not yet.
bool group_all(bool mine);

}  // namespace geodem::comm
