#include "base/exact_sum.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace geodem {

void ExactSum::add_non_finite(double x) {
  ++limb_[std::isnan(x) ? kNaN : x > 0.0 ? kPosInf : kNegInf];
}

void ExactSum::add(const ExactSum& other) {
  // A limb holds less than (pending_ + 1) 2^32 in magnitude: the limbs of two accumulators add
  // as they are, and the bound adds too.
  for (std::size_t k = 0; k < limb_.size(); ++k) limb_[k] += other.limb_[k];
  pending_ += other.pending_ + 1;
  if (pending_ >= kNormaliseEvery) normalise();
}

void ExactSum::normalise() {
  // Digits below the lowest non-zero one stay 0; past the highest non-zero one (below the top)
  // the carry only ripples: once it is 0 or -1, the digits above become 0 or 2^32 - 1 and the
  // top digit takes it. A sum spans a few digits: this is a few steps, not 68.
  constexpr int top = kDigits - 1;
  int lo = 0;
  while (lo < top && limb_[static_cast<std::size_t>(lo)] == 0) ++lo;
  int hi = top - 1;
  while (hi > lo && limb_[static_cast<std::size_t>(hi)] == 0) --hi;
  std::int64_t carry = 0;
  int k = lo;
  for (; k < top; ++k) {
    auto& digit = limb_[static_cast<std::size_t>(k)];
    const std::int64_t v = digit + carry;
    digit = v & kMask;
    carry = v >> 32;  // floor division (C++20: arithmetic shift)
    if (k >= hi && (carry == 0 || carry == -1)) {
      ++k;
      break;
    }
  }
  for (; carry == -1 && k < top; ++k) limb_[static_cast<std::size_t>(k)] = kMask;
  limb_[top] += carry;
  pending_ = 0;
}

void ExactSum::digit_span(int& lo, int& hi) const {
  lo = 0, hi = kDigits;
  while (lo < kDigits && limb_[static_cast<std::size_t>(lo)] == 0) ++lo;
  while (hi > lo && limb_[static_cast<std::size_t>(hi - 1)] == 0) --hi;
}

void ExactSum::pack(const std::vector<ExactSum>& sums, int lo, int hi, std::int64_t* out) {
  for (const ExactSum& x : sums) {
    for (int d = lo; d < hi; ++d) *out++ = x.limb_[static_cast<std::size_t>(d)];
    for (int c = kDigits; c < kDigits + 3; ++c) *out++ = x.limb_[static_cast<std::size_t>(c)];
  }
}

void ExactSum::unpack(const std::int64_t* in, int lo, int hi, std::vector<ExactSum>& sums) {
  for (ExactSum& x : sums) {
    x.limb_.fill(0);
    for (int d = lo; d < hi; ++d) x.limb_[static_cast<std::size_t>(d)] = *in++;
    for (int c = kDigits; c < kDigits + 3; ++c) x.limb_[static_cast<std::size_t>(c)] = *in++;
  }
}

double ExactSum::value() const {
  if (limb_[kNaN] > 0 || (limb_[kPosInf] > 0 && limb_[kNegInf] > 0))
    return std::numeric_limits<double>::quiet_NaN();
  if (limb_[kPosInf] > 0) return std::numeric_limits<double>::infinity();
  if (limb_[kNegInf] > 0) return -std::numeric_limits<double>::infinity();
  // Read from normalised digits (a reduction over ranks leaves them so; otherwise a copy).
  ExactSum copy;
  if (pending_ != 0) copy = *this, copy.normalise();
  const auto& d = pending_ != 0 ? copy.limb_ : limb_;
  // A negative sum is the two's complement of its magnitude M across the digits: below the
  // lowest non-zero digit j, M's digits are 0; M_j = 2^32 - d_j; above, 2^32 - 1 - d_k.
  const bool negative = d[kDigits - 1] < 0;
  int low = 0;
  if (negative)
    while (d[static_cast<std::size_t>(low)] == 0) ++low;
  auto digit = [&](int k) -> std::uint64_t {
    if (k < 0) return 0;
    const auto v = static_cast<std::uint64_t>(d[static_cast<std::size_t>(k)]) & 0xffffffffu;
    if (!negative) return v;
    return k < low ? 0 : k == low ? (std::uint64_t{1} << 32) - v : 0xffffffffu - v;
  };
  int h = kDigits - 1;
  while (h >= 0 && digit(h) == 0) --h;
  if (h < 0) return 0.0;  // an exact zero is +0
  const double sign = negative ? -1.0 : 1.0;
  // Digit 66 is worth 2^(2112 - 1074): anything there is past the largest double.
  if (h >= 66) return sign * std::numeric_limits<double>::infinity();
  const int top = static_cast<int>(std::bit_width(digit(h)));
  const int length = 32 * h + top;
  if (length <= 53) {  // exact, subnormals included
    const std::uint64_t v = digit(0) | (digit(1) << 32);
    return sign * std::ldexp(static_cast<double>(v), -1074);
  }
  // The three top digits hold 64 + top >= 65 bits: the 53 of the significand, the rounding
  // bit and the first sticky bits; the digits below only say whether anything is left.
  __extension__ using Wide = unsigned __int128;
  const Wide w = (static_cast<Wide>(digit(h)) << 64) | (static_cast<Wide>(digit(h - 1)) << 32) |
                 static_cast<Wide>(digit(h - 2));
  const int below = top + 11;  // bits of w under the significand
  auto mantissa = static_cast<std::uint64_t>(w >> below);
  const bool round = ((w >> (below - 1)) & 1u) != 0;
  bool sticky = (w & ((static_cast<Wide>(1) << (below - 1)) - 1)) != 0;
  for (int k = h - 3; k >= 0 && !sticky; --k) sticky = digit(k) != 0;
  if (round && (sticky || (mantissa & 1u))) ++mantissa;  // to nearest, ties to even
  return sign * std::ldexp(static_cast<double>(mantissa), length - 53 - 1074);
}

}  // namespace geodem
