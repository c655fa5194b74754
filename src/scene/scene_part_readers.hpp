// Readers of the parts of a scene that appear at its top level, in its stages and in the
// Python module's edits (walls, clouds, chains, clumps, boxes, friction), so that each takes
// the same keys with the same checks.
#pragma once

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/toml_reader.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

struct ScenePartContext {
  int dimension = 3;
  std::set<std::string> materials;  // names of the [[materials]]
  std::string default_material;     // the first one
  const std::vector<TemplateSpec>* templates = nullptr;
};

// A vector of `dimension` components.
List read_vector(TableReader& t, const std::string& key, const List& fallback, int dimension);

// A material name among the scene's (default: the first material).
std::string read_material_name(TableReader& t, const std::string& key, const ScenePartContext& c);

// `friction` (coefficient) or `friction_deg`, not both.
double read_friction(TableReader& t, double fallback);

// A [[walls]] entry; `index` numbers default names.
WallSpec read_wall(TableReader& t, const ScenePartContext& c, std::size_t index);

// A [[clouds]] entry.
CloudSpec read_cloud(TableReader& t, const ScenePartContext& c);

// A [[chains]] entry; `index` numbers default names.
ChainSpec read_chain(TableReader& t, const ScenePartContext& c, std::size_t index);

// A [[clumps]] entry (the context's templates must be set).
ClumpSpec read_clump(TableReader& t, const ScenePartContext& c);

// A [stop] table: unbalanced_below, kinetic_below, min_time.
StopSpec read_stop(TableReader& t);
// A [stages.stop] table: the same keys and servo_tolerance.
StopSpec read_stage_stop(TableReader& t);

// A box given by its `min` and `max` corners.
std::pair<List, List> read_box(TableReader& t, int dimension);

}  // namespace geodem
