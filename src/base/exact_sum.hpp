// A sum of doubles that does not depend on the order of its terms: every term is added
// exactly into a wide fixed-point integer (2^-1074 up to past 2^1024, in 32-bit digits held
// in 64-bit limbs), and only value() rounds, once, to the nearest double (ties to even). Two
// accumulators merge by adding their limbs, so partial sums from the ranks of a distributed
// run combine into the same bits however the terms were shared out (domain/).
//
// Written by hand: the reproducible summation libraries (ReproBLAS, xsum) are not packaged
// for Debian, and MPFR's exact sum needs its numbers built first, on the heap.
#pragma once

#include <array>
#include <cstdint>

namespace geodem {

class ExactSum {
 public:
  // Digit k holds bits [32 k, 32 k + 32) of the sum in units of 2^-1074. The largest finite
  // double's top bit is bit 2097: 66 digits, and two more take the carries of up to 2^63 terms.
  static constexpr int kDigits = 68;

  void add(double x);
  void add(const ExactSum& other);
  // The exact sum rounded to the nearest double (ties to even); +-inf past the largest
  // double or when an infinity was added; NaN after a NaN or both infinities.
  double value() const;

  // The raw limbs and counts (for an MPI reduction: add them element by element, then call
  // normalise() on the result).
  std::array<std::int64_t, kDigits + 3>& raw() { return limb_; }
  const std::array<std::int64_t, kDigits + 3>& raw() const { return limb_; }
  // Carries each digit's overflow into the next: every digit but the top one in [0, 2^32).
  void normalise();
  // Before the raw limbs of `parts` accumulators (the ranks) are added: normalises only when
  // the terms added since the last normalise() could make a limb of that sum overflow (a limb
  // holds less than (terms + 1) 2^32: parts x (terms + 1) below 2^30 keeps the sum below 2^62).
  void prepare_merge(int parts) {
    if (static_cast<std::uint64_t>(pending_ + 1) * static_cast<std::uint64_t>(parts) >= (1u << 30))
      normalise();
  }

 private:
  // Digits, then the counts of +inf, -inf and NaN terms (they take no digits).
  std::array<std::int64_t, kDigits + 3> limb_{};
  std::uint32_t pending_ = 0;  // terms added since the last normalise()
};

}  // namespace geodem
