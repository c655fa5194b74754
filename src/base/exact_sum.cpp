#include "base/exact_sum.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace geodem {

namespace {
constexpr std::int64_t kMask = 0xffffffff;
constexpr int kPosInf = ExactSum::kDigits, kNegInf = ExactSum::kDigits + 1,
              kNaN = ExactSum::kDigits + 2;
// A digit moves by less than 2^32 per term: 2^30 terms stay far from int64's limit.
constexpr std::uint32_t kNormaliseEvery = 1u << 30;
}  // namespace

void ExactSum::add(double x) {
  if (!std::isfinite(x)) {
    ++limb_[std::isnan(x) ? kNaN : x > 0.0 ? kPosInf : kNegInf];
    return;
  }
  if (x == 0.0) return;
  // x = m 2^p units of 2^-1074: m the 53-bit significand (52 bits when subnormal).
  const auto bits = std::bit_cast<std::uint64_t>(x);
  const auto biased = static_cast<int>((bits >> 52) & 0x7ff);
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
  if (++pending_ >= kNormaliseEvery) normalise();
}

void ExactSum::add(const ExactSum& other) {
  ExactSum o = other;
  o.normalise();
  normalise();
  for (std::size_t k = 0; k < limb_.size(); ++k) limb_[k] += o.limb_[k];
  pending_ = 2;  // each digit now below 2^33
}

void ExactSum::normalise() {
  for (std::size_t k = 0; k + 1 < kDigits; ++k) {
    const std::int64_t carry = limb_[k] >> 32;  // floor division (C++20: arithmetic shift)
    limb_[k] &= kMask;
    limb_[k + 1] += carry;
  }
  pending_ = 0;
}

double ExactSum::value() const {
  if (limb_[kNaN] > 0 || (limb_[kPosInf] > 0 && limb_[kNegInf] > 0))
    return std::numeric_limits<double>::quiet_NaN();
  if (limb_[kPosInf] > 0) return std::numeric_limits<double>::infinity();
  if (limb_[kNegInf] > 0) return -std::numeric_limits<double>::infinity();
  ExactSum a = *this;
  a.normalise();
  auto& d = a.limb_;
  const bool negative = d[kDigits - 1] < 0;
  if (negative) {
    for (std::size_t k = 0; k < kDigits; ++k) d[k] = -d[k];
    a.normalise();
  }
  int h = kDigits - 1;
  while (h >= 0 && d[static_cast<std::size_t>(h)] == 0) --h;
  if (h < 0) return 0.0;  // an exact zero is +0
  const double sign = negative ? -1.0 : 1.0;
  // Digit 66 is worth 2^(2112 - 1074): anything there is past the largest double.
  if (h >= 66) return sign * std::numeric_limits<double>::infinity();
  auto bit = [&](int pos) {
    return (static_cast<std::uint64_t>(d[static_cast<std::size_t>(pos / 32)]) >> (pos % 32)) & 1u;
  };
  const int length =
      32 * h +
      static_cast<int>(std::bit_width(static_cast<std::uint64_t>(d[static_cast<std::size_t>(h)])));
  if (length <= 53) {  // exact, subnormals included
    const auto v = static_cast<std::uint64_t>(d[0]) | (static_cast<std::uint64_t>(d[1]) << 32);
    return sign * std::ldexp(static_cast<double>(v), -1074);
  }
  const int shift = length - 53;
  std::uint64_t mantissa = 0;
  for (int pos = length - 1; pos >= shift; --pos) mantissa = (mantissa << 1) | bit(pos);
  const bool round = bit(shift - 1) != 0;
  bool sticky = false;
  for (int k = 0; k < (shift - 1) / 32 && !sticky; ++k)
    sticky = d[static_cast<std::size_t>(k)] != 0;
  for (int pos = ((shift - 1) / 32) * 32; pos < shift - 1 && !sticky; ++pos) sticky = bit(pos) != 0;
  if (round && (sticky || (mantissa & 1u))) ++mantissa;  // to nearest, ties to even
  return sign * std::ldexp(static_cast<double>(mantissa), shift - 1074);
}

}  // namespace geodem
