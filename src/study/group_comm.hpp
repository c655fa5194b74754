// The communicator of this rank's group of a study (study/study_comm.hpp): what a decomposed
// run's messages go over (distributed/mpi_domain_comm.cpp). MPI_COMM_WORLD without a split.
#pragma once

#ifdef GEODEM_HAVE_MPI
#include <mpi.h>

namespace geodem::comm {
MPI_Comm group_communicator();
}  // namespace geodem::comm
#endif
