// Which failure mechanism a pull-out exhibits (docs/lab_tests.md, "Design methods"):
// slippage at the interface (the soil stays, the sheet slides past it) or deformation of
// the anchoring soil mass (the soil next to the sheet moves with it). Two measures, taken
// at the peak tension:
// - soil_ratio: median displacement of the anchoring soil over the pull displacement;
// - sheet_slip_ratio: 1 - (mean displacement of the grains next to the sheet) / (mean
//   displacement of the sheet's embedded nodes): 1 when the sheet slides past still
//   soil, 0 when the soil beside it moves with it.
#pragma once

#include <string>
#include <vector>

#include "world/world.hpp"

namespace geodem {

// The grains `P` (a world's, or a decomposed world's gathered: scene/scene_domain.hpp) whose
// centre lies within `reach` of the axis of the chains `S`, by index in `P`.
std::vector<char> grains_near_sheet(const Particles<2>& P, const SparChains<2>& S, double reach);

// Mean displacement magnitude of the selected grains of `P` from their start positions (both
// by grain id), and of the nodes with x > 0 (inside the box) from theirs.
double mean_grain_displacement(const Particles<2>& P, const std::vector<char>& selected_by_id,
                               const std::vector<Dim<2>::Vec>& start_by_id);
double mean_embedded_node_displacement(const World<2>& w,
                                       const std::vector<Dim<2>::Vec>& node_start);

struct Mechanism {
  double soil_ratio = 0.0;
  double sheet_slip_ratio = 1.0;
  std::string name;  // "slippage" or "soil_mass"
};

// Slippage: the anchoring soil moved less than 5 % of the pull, and the grains next to
// the sheet less than half as far as the sheet.
Mechanism classify_mechanism(double soil_ratio, double sheet_slip_ratio);

}  // namespace geodem
