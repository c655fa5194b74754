// A scene that starts from another scene run's checkpoint ([start] checkpoint): its grains,
// clumps, walls, chains, bonds and contact springs, with this scenario's settings.
#pragma once

#include "scene/scene_settings.hpp"
#include "world/world.hpp"

namespace geodem {

// Replaces the grains, walls and chains of `world` (built from `s`, without grains) with the
// checkpoint's, then adds the scenario's own walls and applies its settings: materials and
// pair laws, gravity, damping, time step, neighbour search. Time and step start at zero.
// Throws InputError naming [start] when the checkpoint cannot be read or does not fit (kind,
// dimension, materials).
template <int D>
void start_from_checkpoint(const SceneSettings& s, World<D>& world);

}  // namespace geodem
