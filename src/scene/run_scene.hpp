// Runs a `kind = "scene"` scenario to its end, writing history.csv, VTK snapshots,
// summary.json and plots into the output folder.
#pragma once

#include <nlohmann/json.hpp>

#include "io/run_output.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

// Returns the summary written to summary.json. Throws InstabilityError (after
// writing what it has) when the run goes unstable.
nlohmann::json run_scene(const SceneSettings& settings, const RunOptions& options);

}  // namespace geodem
