#include "lab/sheet_parts.hpp"

#include <algorithm>
#include <limits>

namespace geodem {

SheetPartLoads sheet_part_loads(const SparChains<2>& sheet,
                                const std::optional<Dim<2>::Vec>& corner, double band) {
  SheetPartLoads r;
  if (sheet.chains.empty()) return r;
  const auto& c = sheet.chains.front();
  const std::size_t first = c.first_element, n = c.node_count - 1;
  if (n == 0) return r;
  auto normal_of = [&](std::size_t e) {
    return e < sheet.contact_normal.size() ? sheet.contact_normal[e] : 0.0;
  };
  // The bend's elements, [bend_begin, bend_end) in chain order; empty without a corner.
  std::size_t bend_begin = n, bend_end = n;
  if (corner) {
    std::size_t nearest = 0;
    double nearest_d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t e = first + k;
      const double d =
          (0.5 * (sheet.pos[sheet.node_a[e]] + sheet.pos[sheet.node_b[e]]) - *corner).norm();
      if (d < nearest_d) nearest_d = d, nearest = k;
      if (d < band) {
        if (bend_begin == n) bend_begin = k;
        bend_end = k + 1;
      }
    }
    if (bend_begin == n) bend_begin = nearest, bend_end = nearest + 1;
  }
  auto part_of = [&](std::size_t k) {
    return k < bend_begin ? kRunoutPart : k < bend_end ? kBendPart : kTrenchPart;
  };
  // The tension where each part begins: the first element's (the clamp's for the run-out);
  // a part with no element begins where the next one does.
  std::array<double, kSheetParts + 1> begins{};
  std::array<bool, kSheetParts> seen{};
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t p = part_of(k);
    if (!seen[p]) seen[p] = true, begins[p] = sheet.tension[first + k];
    r.normal[p] += normal_of(first + k);  // sums of compressive forces only
  }
  begins[kSheetParts] = 0.0;  // the anchored end is free
  for (std::size_t p = kSheetParts; p-- > 0;)
    if (!seen[p]) begins[p] = begins[p + 1];
  for (std::size_t p = 0; p < kSheetParts; ++p) r.carried[p] = begins[p] - begins[p + 1];
  return r;
}

}  // namespace geodem
