// Turns scene settings into a World: materials, pair laws, walls, grains.
#pragma once

#include <string>
#include <vector>

#include "base/random.hpp"
#include "particles/random_cloud.hpp"
#include "scene/scene_settings.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
void build_world(const SceneSettings& s, World<D>& world);

// The walls a [[walls]] entry stands for (a polyline: one segment per side).
template <int D>
std::vector<Wall<D>> walls_of(const WallSpec& spec, const std::vector<Material>& materials);

// Adds a cloud's grains (or clumps) at random in its box, clear of `placed` (which gains
// them); `key` names the cloud in errors.
template <int D>
void add_cloud(const SceneSettings& s, const CloudSpec& cloud, const std::string& key,
               World<D>& world, Random& rng, std::vector<Sphere<D>>& placed);

// Adds a [[chains]] entry's chain (its nodes at the given points, split into elements) after
// the chains already there; grains find it at the next list build.
template <int D>
void add_chain_spec(const ChainSpec& c, const SceneSettings& s, World<D>& world);

// Adds a [[clumps]] entry's clump; returns its bounding sphere.
template <int D>
Sphere<D> add_clump_spec(const ClumpSpec& c, const SceneSettings& s, World<D>& world);

}  // namespace geodem
