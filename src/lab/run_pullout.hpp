// Runs a `kind = "pullout"` scenario and writes its output folder.
#pragma once

#include <nlohmann/json.hpp>

#include "io/run_output.hpp"
#include "lab/pullout_settings.hpp"

namespace geodem {

nlohmann::json run_pullout(const PulloutSettings& settings, const RunOptions& options);

}  // namespace geodem
