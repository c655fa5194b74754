// The dynamic state of a World as a binary archive (checkpoints): everything a step reads
// or writes, so that a run resumed from it continues bit for bit like one never stopped.
// What the scenario alone determines (material names, wall and chain names, controllers'
// settings) is rebuilt from the scenario; the names and counts are checked on loading.
#pragma once

#include "base/state_archive.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
void save_world_state(StateWriter& out, const World<D>& world);

// Overwrites world's dynamic state; world must have been built from the same scenario
// (same walls, chains, materials, controllers). Throws CheckpointError otherwise.
template <int D>
void load_world_state(StateReader& in, World<D>& world);

// The same for a world whose walls or chains may differ from the saved one (walls added or
// removed between steps, as a script does; a scene that starts from another run's state):
// the saved walls and chains replace the world's, and the controllers' states are not read
// (the world's controllers are left as they are). Materials must still match by name.
template <int D>
void load_world_state_with_walls(StateReader& in, World<D>& world);

}  // namespace geodem
