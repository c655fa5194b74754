// Turns scene settings into a World: materials, pair laws, walls, grains.
#pragma once

#include "scene/scene_settings.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
void build_world(const SceneSettings& s, World<D>& world);

}  // namespace geodem
