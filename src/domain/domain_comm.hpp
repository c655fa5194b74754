// The messages a decomposed domain (domain/slab_domain.hpp) needs between its ranks: bytes to
// and from the two neighbouring slabs, and reductions that every rank receives. The engine
// sees only this interface; MPI implements it in the app layer (distributed/), and the tests
// with ranks as threads (tests/validation/domain_test.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include "base/exact_sum.hpp"

namespace geodem {

using Bytes = std::vector<std::byte>;

class DomainComm {
 public:
  virtual ~DomainComm() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Sends `to_lower` to rank - 1 and `to_upper` to rank + 1 (ignored where there is no such
  // rank) and receives what they sent this rank (left empty where there is none). With `ring`
  // (a periodic cell's slabs) the first and last ranks are neighbours: rank 0's lower is the
  // last rank (with two ranks, each is the other's lower and upper; the messages stay apart).
  virtual void exchange(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                        Bytes& from_upper) = 0;
  bool ring = false;
  virtual double max(double here) = 0;
  virtual double min(double here) = 0;
  // Adds every rank's sums element by element, exactly: the result does not depend on how the
  // terms were shared between ranks.
  virtual void sum(std::vector<ExactSum>& sums) = 0;
  // Every rank's bytes, concatenated in rank order, on every rank.
  virtual Bytes all_gather(const Bytes& here) = 0;
  // The same on rank 0 only (the others get nothing back): the outputs one rank writes.
  virtual Bytes gather(const Bytes& here) = 0;
};

}  // namespace geodem
