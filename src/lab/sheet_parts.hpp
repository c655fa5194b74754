// The pulled sheet split into the parts a design method treats apart (docs/anchorage_design.md,
// "Where the tension goes"): the run-out (the clamp's side of the anchor's bend, the free
// length outside the box included), the bend, and the part beyond it (the L's trench face, the
// V's flank). For each part: the tension it takes off the sheet and the normal force of the
// grains on it, so that a run can be held against each term of the estimate (F1 against the
// run-out, the capstan factor against the bend, F2 against the trench part) instead of their
// sum only.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include "structures/spar_chains.hpp"

namespace geodem {

enum SheetPart : std::size_t { kRunoutPart = 0, kBendPart = 1, kTrenchPart = 2 };
constexpr std::size_t kSheetParts = 3;

struct SheetPartLoads {
  // Tension taken off the sheet along each part: the tension where the part begins (clamp
  // side) less the tension where the next begins; the parts' sum is the clamp's tension.
  std::array<double, kSheetParts> carried{};
  // Sum of the grains' normal forces on the part's elements, both faces (N/m).
  std::array<double, kSheetParts> normal{};

  SheetPartLoads& operator+=(const SheetPartLoads& o) {
    for (std::size_t p = 0; p < kSheetParts; ++p)
      carried[p] += o.carried[p], normal[p] += o.normal[p];
    return *this;
  }
  SheetPartLoads scaled(double f) const {
    SheetPartLoads r;
    for (std::size_t p = 0; p < kSheetParts; ++p)
      r.carried[p] = f * carried[p], r.normal[p] = f * normal[p];
    return r;
  }
  // The tension where the bend begins over where it ends (the measured capstan factor); 0
  // when nothing reaches past the bend.
  double bend_ratio() const {
    const double out = carried[kTrenchPart];
    return out > 0.0 ? (carried[kBendPart] + out) / out : 0.0;
  }
  // Tension taken off over normal force on a part: the friction coefficient it mobilises
  // (both faces, adhesion included); 0 where no grain presses on it.
  double mobilised(std::size_t p) const { return normal[p] > 0.0 ? carried[p] / normal[p] : 0.0; }
};

// The parts of chain 0 of `sheet` now: an element whose midpoint is within `band` of the
// bend `corner` belongs to the bend, and so does every element between the first and the
// last of those; the elements before it to the run-out, those after it to the trench part.
// When no midpoint is that close, the element nearest the corner is the bend. Without a
// corner (a run-out anchor) the whole sheet is run-out. Reads the elements' tension and
// contact_normal of the last step.
SheetPartLoads sheet_part_loads(const SparChains<2>& sheet,
                                const std::optional<Dim<2>::Vec>& corner, double band);

}  // namespace geodem
