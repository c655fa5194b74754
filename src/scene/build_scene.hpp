// Turns scene settings into a World: materials, pair laws, walls, grains.
#pragma once

#include "core/world.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

template <int D>
void build_world(const SceneSettings& s, World<D>& world);

}  // namespace geodem
