// The [[stages]] of a scene: each changes the world at its start (walls removed, added or
// set moving, grains removed or added, gravity, damping, friction) and then runs until its
// duration, step count or stop criteria.
#pragma once

#include <vector>

#include "io/toml_reader.hpp"
#include "scene/scene_part_readers.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

// Reads and checks the stages against the scene read so far (walls, chains): a wall named in
// a stage exists at that stage, a servo drives a plane wall with an area.
std::vector<StageSpec> read_stages(TableReader& root, const ScenePartContext& parts,
                                   const SceneSettings& scene);

}  // namespace geodem
