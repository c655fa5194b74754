#include "lab/anchorage_mechanism.hpp"

#include <algorithm>

namespace geodem {

std::vector<char> grains_near_sheet(const Particles<2>& P, const SparChains<2>& S, double reach) {
  std::vector<char> near(P.size(), 0);
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::size_t e = 0; e < S.elements() && !near[i]; ++e) {
      const Dim<2>::Vec a = S.pos[S.node_a[e]], b = S.pos[S.node_b[e]], ab = b - a;
      const double t = std::clamp((P.pos[i] - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      near[i] = (a + t * ab - P.pos[i]).norm() < reach ? 1 : 0;
    }
  return near;
}

double mean_grain_displacement(const Particles<2>& P, const std::vector<char>& selected_by_id,
                               const std::vector<Dim<2>::Vec>& start_by_id) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (selected_by_id[P.id[i]]) sum += (P.pos[i] - start_by_id[P.id[i]]).norm(), ++n;
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

double mean_embedded_node_displacement(const World<2>& w,
                                       const std::vector<Dim<2>::Vec>& node_start) {
  const auto& S = w.spars;
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < S.nodes(); ++i)
    if (node_start[i].x() > 0.0) sum += (S.pos[i] - node_start[i]).norm(), ++n;
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

Mechanism classify_mechanism(double soil_ratio, double sheet_slip_ratio) {
  Mechanism m;
  m.soil_ratio = soil_ratio;
  m.sheet_slip_ratio = sheet_slip_ratio;
  m.name = soil_ratio < 0.05 && sheet_slip_ratio > 0.5 ? "slippage" : "soil_mass";
  return m;
}

}  // namespace geodem
