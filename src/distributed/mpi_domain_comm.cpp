#include "distributed/mpi_domain_comm.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "study/group_comm.hpp"

namespace geodem {

#ifdef GEODEM_HAVE_MPI
namespace {

int count_of(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(INT_MAX))
    throw std::runtime_error("a domain message of " + std::to_string(bytes) +
                             " bytes is past MPI's int count: use more ranks");
  return static_cast<int>(bytes);
}

class MpiDomainComm final : public DomainComm {
 public:
  // The ranks of this rank's group of a study's runs (all of them but in a study split with
  // --ranks-per-run).
  MpiDomainComm() : comm_(comm::group_communicator()) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void exchange(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                Bytes& from_upper) override {
    // The neighbours: none past the ends, unless the slabs close in a ring (of two ranks or more).
    const bool ring_here = ring && size_ > 1;
    const int lower = rank_ > 0 ? rank_ - 1 : ring_here ? size_ - 1 : MPI_PROC_NULL;
    const int upper = rank_ + 1 < size_ ? rank_ + 1 : ring_here ? 0 : MPI_PROC_NULL;
    // Sizes first (upwards, then downwards), then the bytes.
    std::uint64_t up_n = to_upper.size(), down_n = to_lower.size(), from_lo = 0, from_up = 0;
    MPI_Sendrecv(&up_n, 1, MPI_UINT64_T, upper, 0, &from_lo, 1, MPI_UINT64_T, lower, 0, comm_,
                 MPI_STATUS_IGNORE);
    MPI_Sendrecv(&down_n, 1, MPI_UINT64_T, lower, 1, &from_up, 1, MPI_UINT64_T, upper, 1, comm_,
                 MPI_STATUS_IGNORE);
    from_lower.resize(from_lo);
    from_upper.resize(from_up);
    MPI_Sendrecv(to_upper.data(), count_of(up_n), MPI_BYTE, upper, 2, from_lower.data(),
                 count_of(from_lo), MPI_BYTE, lower, 2, comm_, MPI_STATUS_IGNORE);
    MPI_Sendrecv(to_lower.data(), count_of(down_n), MPI_BYTE, lower, 3, from_upper.data(),
                 count_of(from_up), MPI_BYTE, upper, 3, comm_, MPI_STATUS_IGNORE);
  }
  double max(double here) override {
    double out = here;
    MPI_Allreduce(&here, &out, 1, MPI_DOUBLE, MPI_MAX, comm_);
    return out;
  }
  double min(double here) override {
    double out = here;
    MPI_Allreduce(&here, &out, 1, MPI_DOUBLE, MPI_MIN, comm_);
    return out;
  }
  void sum(std::vector<ExactSum>& sums) override {
    // Integer limbs: their sum is exact in any order (and normalised once, after it). Only the
    // digits some rank's sum has non-zero travel: the window of digits is agreed first (one
    // small message), when the sums are many enough for it to pay (a step's walls, cell or
    // sheet: 568 bytes a sum in full, a few digits in use).
    int lo = 0, hi = ExactSum::kDigits;
    for (auto& x : sums) x.prepare_merge(size_);
    if (size_ > 1 && sums.size() >= kWindowedFrom) {
      int span[2] = {ExactSum::kDigits, 0};  // the lowest digit in use, less the highest
      for (const auto& x : sums) {
        int a = 0, b = 0;
        x.digit_span(a, b);
        if (a < b) span[0] = std::min(span[0], a), span[1] = std::min(span[1], -b);
      }
      MPI_Allreduce(MPI_IN_PLACE, span, 2, MPI_INT, MPI_MIN, comm_);
      lo = span[0], hi = std::max(-span[1], lo);
    }
    const auto width = static_cast<std::size_t>(hi - lo + 3);
    limbs_.resize(sums.size() * width), total_.resize(limbs_.size());
    ExactSum::pack(sums, lo, hi, limbs_.data());
    MPI_Allreduce(limbs_.data(), total_.data(), count_of(limbs_.size()), MPI_INT64_T, MPI_SUM,
                  comm_);
    ExactSum::unpack(total_.data(), lo, hi, sums);
    for (auto& x : sums) x.normalise();
  }
  Bytes gather(const Bytes& here) override {
    const int n = count_of(here.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(counts.size(), 0);
    MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_);
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts.size() && rank_ == 0; ++r) {
      offsets[r] = count_of(total);
      total += static_cast<std::size_t>(counts[r]);
    }
    Bytes out(total);
    MPI_Gatherv(here.data(), n, MPI_BYTE, out.data(), counts.data(), offsets.data(), MPI_BYTE, 0,
                comm_);
    return out;
  }
  Bytes all_gather(const Bytes& here) override {
    const int n = count_of(here.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(counts.size(), 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      offsets[r] = count_of(total);
      total += static_cast<std::size_t>(counts[r]);
    }
    Bytes out(total);
    MPI_Allgatherv(here.data(), n, MPI_BYTE, out.data(), counts.data(), offsets.data(), MPI_BYTE,
                   comm_);
    return out;
  }

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  std::vector<std::int64_t> limbs_, total_;        // kept: a step's reduction allocates nothing
  static constexpr std::size_t kWindowedFrom = 8;  // sums a reduction before it is windowed
};

}  // namespace
#endif

std::shared_ptr<DomainComm> mpi_domain_comm() {
#ifdef GEODEM_HAVE_MPI
  int ready = 0;
  MPI_Initialized(&ready);
  if (!ready) throw std::runtime_error("MPI is not initialised (run under mpirun)");
  return std::make_shared<MpiDomainComm>();
#else
  throw std::runtime_error("this geodem was built without MPI: install libopenmpi-dev and rebuild");
#endif
}

}  // namespace geodem
