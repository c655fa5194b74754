#include "clumps/grain_mix.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "clumps/clumps.hpp"
#include "particles/random_cloud.hpp"

namespace geodem {

bool is_round_shape(const std::string& shape) {
  return shape == "sphere" || shape == "disc";
}

bool GrainSpec::round_only() const {
  return kinds.size() == 1 && is_round_shape(kinds[0].shape);
}

template <int D>
ResolvedClump<D> resolve_shape(const std::string& shape,
                               const std::vector<TemplateSpec>& templates) {
  using Vec = typename Dim<D>::Vec;
  ClumpTemplate<D> t;
  if (is_round_shape(shape)) {
    builtin_clump_template<D>("sphere", t);
  } else if (!builtin_clump_template<D>(shape, t)) {
    const auto it = std::find_if(templates.begin(), templates.end(),
                                 [&](const TemplateSpec& s) { return s.name == shape; });
    if (it == templates.end()) throw std::invalid_argument("unknown grain " + shape);
    t.name = shape;
    for (const auto& m : it->members) {
      Vec c;
      for (int a = 0; a < D; ++a) c[a] = m[static_cast<std::size_t>(a)];
      t.centre.push_back(c);
      t.radius.push_back(m.back());
    }
  }
  return resolve_clump(t);
}

template <int D>
std::vector<ResolvedKind<D>> resolve_kinds(const GrainSpec& spec) {
  std::vector<ResolvedKind<D>> out;
  double total = 0.0;
  for (const auto& k : spec.kinds) total += k.fraction;
  for (const auto& k : spec.kinds) {
    ResolvedKind<D> r;
    r.size = k.size;
    r.fraction = k.fraction / total;
    r.round = is_round_shape(k.shape);
    r.clump = resolve_shape<D>(k.shape, spec.templates);
    out.push_back(r);
  }
  return out;
}

template <int D>
double add_random_grains(World<D>& world, const std::vector<ResolvedKind<D>>& kinds,
                         const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                         std::size_t count, double porosity, double fuzz, double density,
                         std::uint16_t material, Random& rng, const typename Dim<D>::Vec& velocity,
                         double mean_scale, std::vector<Sphere<D>>* existing) {
  // Counts per kind: rounded fractions, the last kind takes the remainder.
  std::vector<std::size_t> counts(kinds.size(), 0);
  std::size_t assigned = 0;
  for (std::size_t k = 0; k + 1 < kinds.size(); ++k) {
    counts[k] =
        static_cast<std::size_t>(std::llround(kinds[k].fraction * static_cast<double>(count)));
    assigned += counts[k];
  }
  counts.back() = count > assigned ? count - assigned : 0;
  // E[(1 + fuzz u)^D] for u uniform in [-1, 1].
  const double moment = D == 3 ? 1.0 + fuzz * fuzz : 1.0 + fuzz * fuzz / 3.0;
  double unit_solid = 0.0;
  for (std::size_t k = 0; k < kinds.size(); ++k)
    unit_solid += static_cast<double>(counts[k]) * kinds[k].clump.volume *
                  std::pow(kinds[k].size, D) * moment;
  const double box = (hi - lo).prod();
  const double mean =
      mean_scale > 0.0 ? mean_scale : std::pow((1.0 - porosity) * box / unit_solid, 1.0 / D);
  struct Pending {
    double bound, scale;
    std::size_t kind;
  };
  std::vector<Pending> grains;
  grains.reserve(count);
  for (std::size_t k = 0; k < kinds.size(); ++k)
    for (std::size_t g = 0; g < counts[k]; ++g) {
      const double s = mean * kinds[k].size * (1.0 + fuzz * (2.0 * rng.uniform() - 1.0));
      grains.push_back({s * kinds[k].clump.bounding_radius, s, k});
    }
  std::stable_sort(grains.begin(), grains.end(),
                   [](const Pending& a, const Pending& b) { return a.bound > b.bound; });
  std::vector<double> bounds(grains.size());
  for (std::size_t g = 0; g < grains.size(); ++g) bounds[g] = grains[g].bound;
  std::vector<Sphere<D>> placed;
  try {
    placed = place_random<D>(lo, hi, bounds, rng, existing ? *existing : std::vector<Sphere<D>>{});
  } catch (const std::runtime_error& e) {
    // Clumps are placed by their bounding spheres: say how much room those take.
    double bound_volume = 0.0, solid = 0.0;
    for (const auto& g : grains) {
      bound_volume += Dim<D>::volume(g.bound);
      solid += kinds[g.kind].clump.volume * std::pow(g.scale, D);
    }
    if (bound_volume <= 1.0001 * solid) throw;
    throw std::runtime_error(std::string(e.what()) + "; clumps are placed by their bounding " +
                             (D == 3 ? "spheres" : "discs") + ", which fill " +
                             std::to_string(bound_volume / solid).substr(0, 4) +
                             " times their volume: raise the initial porosity");
  }
  if (existing) existing->insert(existing->end(), placed.begin(), placed.end());
  world.particles.reserve(world.particles.size() + grains.size() * 2);
  for (std::size_t g = 0; g < grains.size(); ++g) {
    const auto& kind = kinds[grains[g].kind];
    if (kind.round) {
      world.particles.add(placed[g].centre, grains[g].scale, density, material, velocity);
    } else {
      const auto q = random_orientation<D>(rng.uniform(), rng.uniform(), rng.uniform());
      add_clump(world, kind.clump, placed[g].centre, q, grains[g].scale, density, material,
                velocity);
    }
  }
  return mean;
}

template std::vector<ResolvedKind<2>> resolve_kinds<2>(const GrainSpec&);
template std::vector<ResolvedKind<3>> resolve_kinds<3>(const GrainSpec&);
template double add_random_grains<2>(World<2>&, const std::vector<ResolvedKind<2>>&,
                                     const Dim<2>::Vec&, const Dim<2>::Vec&, std::size_t, double,
                                     double, double, std::uint16_t, Random&, const Dim<2>::Vec&,
                                     double, std::vector<Sphere<2>>*);
template ResolvedClump<2> resolve_shape<2>(const std::string&, const std::vector<TemplateSpec>&);
template ResolvedClump<3> resolve_shape<3>(const std::string&, const std::vector<TemplateSpec>&);
template double add_random_grains<3>(World<3>&, const std::vector<ResolvedKind<3>>&,
                                     const Dim<3>::Vec&, const Dim<3>::Vec&, std::size_t, double,
                                     double, double, std::uint16_t, Random&, const Dim<3>::Vec&,
                                     double, std::vector<Sphere<3>>*);

}  // namespace geodem
