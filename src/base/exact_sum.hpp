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
#include <bit>
#include <cstdint>
#include <vector>

namespace geodem {

class ExactSum {
 public:
  // Digit k holds bits [32 k, 32 k + 32) of the sum in units of 2^-1074. The largest finite
  // double's top bit is bit 2097: 66 digits, and two more take the carries of up to 2^63 terms.
  static constexpr int kDigits = 68;

  // Inline: a decomposed periodic cell adds a dozen terms per contact every step.
  void add(double x) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const auto biased = static_cast<int>((bits >> 52) & 0x7ff);
    if (biased == 0x7ff) [[unlikely]] {
      add_non_finite(x);
      return;
    }
    if ((bits << 1) == 0) return;  // +-0
    // x = m 2^p units of 2^-1074: m the 53-bit significand (52 bits when subnormal).
    const std::uint64_t frac = bits & ((std::uint64_t{1} << 52) - 1);
    const std::uint64_t m = biased == 0 ? frac : frac | (std::uint64_t{1} << 52);
    const int p = biased == 0 ? 0 : biased - 1;
    const int k = p / 32, s = p % 32;
    // m << s spans three digits (at most 84 bits).
    const auto d0 = static_cast<std::int64_t>((m << s) & kMask);
    const auto d1 = static_cast<std::int64_t>((s == 0 ? m >> 32 : m >> (32 - s)) & kMask);
    const auto d2 = static_cast<std::int64_t>(s == 0 ? 0 : m >> (64 - s));
    const auto uk = static_cast<std::size_t>(k);
    if (bits >> 63) {
      limb_[uk] -= d0, limb_[uk + 1] -= d1, limb_[uk + 2] -= d2;
    } else {
      limb_[uk] += d0, limb_[uk + 1] += d1, limb_[uk + 2] += d2;
    }
    if (++pending_ >= kNormaliseEvery) [[unlikely]]
      normalise();
  }
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
  // The digits [lo, hi) outside which every digit is 0 (lo >= hi: none), and the sums' raw
  // limbs packed over a window of digits [lo, hi) that holds every non-zero one, then the
  // three counts: (hi - lo + 3) limbs a sum. Unpacking sets the other digits to 0. (A
  // reduction over ranks then sends the few digits a step's sums span, not all 68.)
  void digit_span(int& lo, int& hi) const;
  static void pack(const std::vector<ExactSum>& sums, int lo, int hi, std::int64_t* out);
  static void unpack(const std::int64_t* in, int lo, int hi, std::vector<ExactSum>& sums);
  // Before the raw limbs of `parts` accumulators (the ranks) are added: normalises only when
  // the terms added since the last normalise() could make a limb of that sum overflow (a limb
  // holds less than (terms + 1) 2^32: parts x (terms + 1) below 2^30 keeps the sum below 2^62).
  void prepare_merge(int parts) {
    if (static_cast<std::uint64_t>(pending_ + 1) * static_cast<std::uint64_t>(parts) >= (1u << 30))
      normalise();
  }

 private:
  static constexpr std::int64_t kMask = 0xffffffff;
  static constexpr int kPosInf = kDigits, kNegInf = kDigits + 1, kNaN = kDigits + 2;
  // A digit moves by less than 2^32 per term: 2^30 terms stay far from int64's limit.
  static constexpr std::uint32_t kNormaliseEvery = 1u << 30;
  void add_non_finite(double x);
  // Digits, then the counts of +inf, -inf and NaN terms (they take no digits).
  std::array<std::int64_t, kDigits + 3> limb_{};
  std::uint32_t pending_ = 0;  // terms added since the last normalise()
};

}  // namespace geodem
