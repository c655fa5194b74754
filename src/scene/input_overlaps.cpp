#include "scene/input_overlaps.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "base/error.hpp"

namespace geodem {

template <int D>
void reject_input_overlaps(const std::vector<Sphere<D>>& g,
                           const std::function<std::string(std::size_t)>& name, double limit,
                           const std::string& scenario) {
  using Vec = typename Dim<D>::Vec;
  const std::size_t n = g.size();
  if (n < 2) return;
  Vec lo = g[0].centre, hi = g[0].centre;
  double rmax = 0.0;
  for (const auto& s : g) {
    lo = lo.cwiseMin(s.centre);
    hi = hi.cwiseMax(s.centre);
    rmax = std::max(rmax, s.radius);
  }
  // Cells of the largest diameter, grown until there are at most about two per grain however
  // far an outlier lies (a larger cell still holds every neighbour within reach).
  double cell = rmax > 0.0 ? 2.0 * rmax : 1.0;
  std::array<std::size_t, 3> dims{1, 1, 1};
  const double max_cells = 2.0 * static_cast<double>(n) + 64.0;
  for (;;) {
    double cells = 1.0;
    for (int k = 0; k < D; ++k) cells *= std::floor((hi[k] - lo[k]) / cell) + 1.0;
    if (cells <= max_cells) break;
    cell *= 1.25;
  }
  for (int k = 0; k < D; ++k)
    dims[k] = static_cast<std::size_t>(std::floor((hi[k] - lo[k]) / cell)) + 1;
  auto coord = [&](const Vec& x, int k) {
    const double c = std::floor((x[k] - lo[k]) / cell);
    return c >= 0.0 ? std::min(static_cast<std::size_t>(c), dims[k] - 1) : std::size_t{0};
  };
  auto cell_of = [&](std::size_t i, std::size_t j, std::size_t k) {
    return (k * dims[1] + j) * dims[0] + i;
  };
  const std::size_t ncells = dims[0] * dims[1] * dims[2];
  // Grains sorted by cell (counting sort); within a cell by index.
  std::vector<std::uint32_t> start(ncells + 1, 0), sorted(n);
  auto cell_of_grain = [&](std::size_t a) {
    const Vec& x = g[a].centre;
    return cell_of(coord(x, 0), coord(x, 1), D == 3 ? coord(x, D - 1) : 0);
  };
  for (std::size_t a = 0; a < n; ++a) ++start[cell_of_grain(a) + 1];
  for (std::size_t c = 0; c < ncells; ++c) start[c + 1] += start[c];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t a = 0; a < n; ++a)
      sorted[fill[cell_of_grain(a)]++] = static_cast<std::uint32_t>(a);
  }
  // Grain a against the earlier grains of its cell and the adjacent ones: the first a that
  // overlaps one is reported, with the earliest such grain.
  for (std::size_t a = 0; a < n; ++a) {
    const Vec& x = g[a].centre;
    std::array<std::size_t, 3> c{coord(x, 0), coord(x, 1), D == 3 ? coord(x, D - 1) : 0};
    std::size_t found = n;
    double deepest = 0.0;
    for (std::size_t k = c[2] > 0 ? c[2] - 1 : 0; k <= std::min(c[2] + 1, dims[2] - 1); ++k)
      for (std::size_t j = c[1] > 0 ? c[1] - 1 : 0; j <= std::min(c[1] + 1, dims[1] - 1); ++j)
        for (std::size_t i = c[0] > 0 ? c[0] - 1 : 0; i <= std::min(c[0] + 1, dims[0] - 1); ++i) {
          const std::size_t id = cell_of(i, j, k);
          for (std::uint32_t s = start[id]; s < start[id + 1]; ++s) {
            const std::size_t b = sorted[s];
            if (b >= a || b >= found) continue;
            const double smaller = std::min(g[a].radius, g[b].radius);
            const double depth = g[a].radius + g[b].radius - (x - g[b].centre).norm();
            if (depth > limit * smaller) found = b, deepest = depth / smaller;
          }
        }
    if (found < n)
      throw InputError(scenario, 0, name(a),
                       "this grain overlaps " + name(found) + " by " +
                           std::to_string(static_cast<int>(100.0 * deepest)) +
                           " % of the smaller radius (the run stops above " +
                           std::to_string(static_cast<int>(100.0 * limit)) +
                           " %): move them apart or make them smaller");
  }
}

template void reject_input_overlaps<2>(const std::vector<Sphere<2>>&,
                                       const std::function<std::string(std::size_t)>&, double,
                                       const std::string&);
template void reject_input_overlaps<3>(const std::vector<Sphere<3>>&,
                                       const std::function<std::string(std::size_t)>&, double,
                                       const std::string&);

}  // namespace geodem
