// Starting a stage of a scene: the world edits its [[stages]] entry asks for.
#pragma once

#include <string>
#include <vector>

#include "scene/scene_settings.hpp"
#include "world/world.hpp"

namespace geodem {

// The walls a scene's wall name stands for: the wall of that name, or the segments of the
// polyline of that name (name_0, name_1, ...).
template <int D>
std::vector<std::size_t> wall_indices(const World<D>& w, const std::string& name);

// Makes the edits of stage `k` at its start. The servos of the previous stage stop (their
// walls come to rest unless this stage moves them); walls are removed, then added; gravity,
// damping and friction are set; grains in the removal boxes leave (the others keep their
// contacts); clouds are added; walls and held chain nodes take their new motions.
// With `replay`, only what a checkpoint does not hold is redone (the wall list and the
// servos): a resumed run rebuilds its world that way before it reads the saved state.
template <int D>
void start_stage(const SceneSettings& s, std::size_t k, World<D>& w, bool replay);

}  // namespace geodem
