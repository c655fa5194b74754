// The grains of a sample: one shape, or a mix of shapes (round grains or clump
// templates) by size and number fraction (scene/grain_spec_reader reads them), and the random
// loose cloud of them that a lab test or a scene starts from.
#pragma once

#include <string>
#include <vector>

#include "base/random.hpp"
#include "clumps/clump_template.hpp"
#include "particles/random_cloud.hpp"
#include "world/world.hpp"

namespace geodem {

struct GrainKind {
  std::string shape = "sphere";  // "sphere"/"disc" (round) or a clump template name
  double size = 1.0;             // relative scale of this kind
  double fraction = 1.0;         // number fraction (normalised over the kinds)
};

struct TemplateSpec {
  std::string name;
  std::vector<std::vector<double>> members;  // rows x, y, (z,) r
};

struct GrainSpec {
  std::vector<GrainKind> kinds{GrainKind{}};
  std::vector<TemplateSpec> templates;  // user templates ([[templates]])
  bool round_only() const;
};

// "sphere" and "disc": the round grain's names.
bool is_round_shape(const std::string& shape);

// The template of one shape name, at unit scale (round grains: one member of radius 1).
template <int D>
ResolvedClump<D> resolve_shape(const std::string& shape,
                               const std::vector<TemplateSpec>& templates);

// A kind ready to place: its template at unit scale (one member of radius 1 for round).
template <int D>
struct ResolvedKind {
  bool round = true;
  ResolvedClump<D> clump;
  double size = 1.0, fraction = 1.0;
};

template <int D>
std::vector<ResolvedKind<D>> resolve_kinds(const GrainSpec& spec);

// Adds `count` grains at random without overlap in [lo, hi] (bounding spheres), sizes
// uniform in scale*(1 +- fuzz) per kind with the mean scale set so that the solid
// fraction is 1 - porosity (or the given mean_scale when > 0); clumps get random
// orientations. `placed` (optional): bounding spheres to keep clear of, to which the new
// grains' are appended. Returns the mean scale.
template <int D>
double add_random_grains(World<D>& world, const std::vector<ResolvedKind<D>>& kinds,
                         const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                         std::size_t count, double porosity, double fuzz, double density,
                         std::uint16_t material, Random& rng,
                         const typename Dim<D>::Vec& velocity = Dim<D>::Vec::Zero(),
                         double mean_scale = 0.0, std::vector<Sphere<D>>* placed = nullptr);

}  // namespace geodem
