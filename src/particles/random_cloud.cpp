#include "particles/random_cloud.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace geodem {

template <int D>
double mean_radius_for_porosity(double volume, std::size_t count, double porosity, double fuzz) {
  const double solid = (1.0 - porosity) * volume / static_cast<double>(count);
  if constexpr (D == 3)
    return std::cbrt(solid / (4.0 / 3.0 * std::numbers::pi * (1.0 + fuzz * fuzz)));
  else
    return std::sqrt(solid / (std::numbers::pi * (1.0 + fuzz * fuzz / 3.0)));
}

template <int D>
std::vector<Sphere<D>> random_cloud(const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                                    std::size_t count, double mean_radius, double fuzz, Random& rng,
                                    const std::vector<Sphere<D>>& existing) {
  std::vector<double> radii(count);
  for (auto& r : radii) r = mean_radius * (1.0 + fuzz * (2.0 * rng.uniform() - 1.0));
  std::sort(radii.begin(), radii.end(), std::greater<>());
  return place_random<D>(lo, hi, radii, rng, existing);
}

template <int D>
std::vector<Sphere<D>> place_random(const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                                    const std::vector<double>& radii, Random& rng,
                                    const std::vector<Sphere<D>>& existing) {
  using Vec = typename Dim<D>::Vec;
  const std::size_t count = radii.size();
  const double rmax = radii.empty() ? 0.0 : *std::max_element(radii.begin(), radii.end());

  // Grid of cells of size 2 rmax over the box; each cell lists the grains in it.
  double emax = 0.0;
  for (const auto& s : existing) emax = std::max(emax, s.radius);
  const double cell = 2.0 * std::max(rmax, emax);
  std::array<int, 3> dims{1, 1, 1};
  for (int k = 0; k < D; ++k)
    dims[k] = std::max(1, static_cast<int>(std::ceil((hi[k] - lo[k]) / cell)));
  const std::size_t ncells = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
  if (ncells > 50'000'000) throw std::runtime_error("cloud box too large for its grain size");
  std::vector<std::vector<std::uint32_t>> cells(ncells);
  std::vector<Sphere<D>> all(existing);
  all.reserve(existing.size() + count);
  auto cell_of = [&](const Vec& x, std::array<int, 3>& c) {
    for (int k = 0; k < 3; ++k)
      c[k] = k < D ? std::clamp(static_cast<int>((x[k] - lo[k]) / cell), 0, dims[k] - 1) : 0;
    return static_cast<std::size_t>((c[2] * dims[1] + c[1]) * dims[0] + c[0]);
  };
  std::array<int, 3> c{};
  for (std::size_t i = 0; i < all.size(); ++i)
    cells[cell_of(all[i].centre, c)].push_back(static_cast<std::uint32_t>(i));

  const int zr = D == 3 ? 1 : 0;
  const int max_tries = 2000;
  for (std::size_t g = 0; g < count; ++g) {
    const double r = radii[g];
    bool placed = false;
    for (int attempt = 0; attempt < max_tries && !placed; ++attempt) {
      Vec x;
      for (int k = 0; k < D; ++k) {
        if (hi[k] - lo[k] < 2.0 * r) throw std::runtime_error("cloud box thinner than a grain");
        x[k] = rng.uniform(lo[k] + r, hi[k] - r);
      }
      cell_of(x, c);
      bool free = true;
      for (int dz = -zr; dz <= zr && free; ++dz)
        for (int dy = -1; dy <= 1 && free; ++dy)
          for (int dx = -1; dx <= 1 && free; ++dx) {
            const int cx = c[0] + dx, cy = c[1] + dy, cz = c[2] + dz;
            if (cx < 0 || cy < 0 || cz < 0 || cx >= dims[0] || cy >= dims[1] || cz >= dims[2])
              continue;
            for (std::uint32_t j :
                 cells[(static_cast<std::size_t>(cz) * dims[1] + cy) * dims[0] + cx]) {
              const double rs = r + all[j].radius;
              if ((all[j].centre - x).squaredNorm() < rs * rs) {
                free = false;
                break;
              }
            }
          }
      if (free) {
        all.push_back({x, r});
        cells[cell_of(x, c)].push_back(static_cast<std::uint32_t>(all.size() - 1));
        placed = true;
      }
    }
    if (!placed)
      throw std::runtime_error("could not place grain " + std::to_string(g + 1) + " of " +
                               std::to_string(count) + " without overlap after " +
                               std::to_string(max_tries) +
                               " tries: the cloud is too dense; enlarge the box, or lower the "
                               "count or the radius (random placement jams near 30-38 % solid)");
  }
  return std::vector<Sphere<D>>(all.begin() + static_cast<std::ptrdiff_t>(existing.size()),
                                all.end());
}

template std::vector<Sphere<2>> random_cloud<2>(const Dim<2>::Vec&, const Dim<2>::Vec&, std::size_t,
                                                double, double, Random&,
                                                const std::vector<Sphere<2>>&);
template std::vector<Sphere<3>> random_cloud<3>(const Dim<3>::Vec&, const Dim<3>::Vec&, std::size_t,
                                                double, double, Random&,
                                                const std::vector<Sphere<3>>&);
template std::vector<Sphere<2>> place_random<2>(const Dim<2>::Vec&, const Dim<2>::Vec&,
                                                const std::vector<double>&, Random&,
                                                const std::vector<Sphere<2>>&);
template std::vector<Sphere<3>> place_random<3>(const Dim<3>::Vec&, const Dim<3>::Vec&,
                                                const std::vector<double>&, Random&,
                                                const std::vector<Sphere<3>>&);
template double mean_radius_for_porosity<2>(double, std::size_t, double, double);
template double mean_radius_for_porosity<3>(double, std::size_t, double, double);

}  // namespace geodem
