// The messages of a decomposed domain (domain/domain_comm.hpp) over MPI: the ranks of
// MPI_COMM_WORLD (of this rank's group, when a study runs its runs on groups of ranks) in
// order are the slabs in order.
#pragma once

#include <memory>

#include "domain/domain_comm.hpp"

namespace geodem {

// Throws std::runtime_error when geodem was built without MPI or MPI is not initialised.
std::shared_ptr<DomainComm> mpi_domain_comm();

}  // namespace geodem
