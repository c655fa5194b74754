// A decomposed domain of one rank without MPI (domain/domain_comm.hpp): a run that resumes a
// decomposed run's checkpoint in one process goes on as a one-rank domain, so that it has the
// bits the decomposed run would have had (they do not depend on the number of ranks).
#pragma once

#include "domain/domain_comm.hpp"

namespace geodem {

class LocalDomainComm final : public DomainComm {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void exchange(const Bytes&, const Bytes&, Bytes& from_lower, Bytes& from_upper) override {
    from_lower.clear(), from_upper.clear();
  }
  double max(double here) override { return here; }
  double min(double here) override { return here; }
  void sum(std::vector<ExactSum>&) override {}
  Bytes all_gather(const Bytes& here) override { return here; }
  Bytes gather(const Bytes& here) override { return here; }
};

}  // namespace geodem
