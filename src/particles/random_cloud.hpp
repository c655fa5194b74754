// Random loose packing: grains placed one by one at random positions inside a box,
// rejecting overlaps (random sequential addition), largest first.
#pragma once

#include <vector>

#include "base/dim.hpp"
#include "base/random.hpp"

namespace geodem {

template <int D>
struct Sphere {
  typename Dim<D>::Vec centre;
  double radius;
};

// The grains of `grains` (Particles) as spheres: what grains added among them must clear.
template <int D, class Grains>
std::vector<Sphere<D>> spheres_of(const Grains& grains) {
  std::vector<Sphere<D>> s;
  s.reserve(grains.size());
  for (std::size_t i = 0; i < grains.size(); ++i) s.push_back({grains.pos[i], grains.radius[i]});
  return s;
}

// Radii uniform in mean*(1 +- fuzz). Grains stay inside [lo, hi] and do not overlap
// each other nor `existing`. Throws std::runtime_error when the box is too full.
template <int D>
std::vector<Sphere<D>> random_cloud(const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                                    std::size_t count, double mean_radius, double fuzz, Random& rng,
                                    const std::vector<Sphere<D>>& existing = {});

// Places spheres of the given radii, in the given order (largest first packs best),
// at random inside [lo, hi] without overlap; returns them in the same order.
template <int D>
std::vector<Sphere<D>> place_random(const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                                    const std::vector<double>& radii, Random& rng,
                                    const std::vector<Sphere<D>>& existing = {});

// Mean radius that gives `porosity` for `count` grains with radii mean*(1 +- fuzz) in a
// box of volume `volume`: uses E[r^3] = mean^3 (1 + fuzz^2) (3D), E[r^2] = mean^2 (1 + fuzz^2/3)
// (2D).
template <int D>
double mean_radius_for_porosity(double volume, std::size_t count, double porosity, double fuzz);

}  // namespace geodem
