// Runs a `kind = "triaxial"` scenario: prepares the sample as the paper (and yade's
// triaxial tutorial) does, then one strain-controlled compression per confining
// stress; writes history.csv, preparation.csv, summary.json, VTK and plots.
#pragma once

#include <nlohmann/json.hpp>

#include "io/run_output.hpp"
#include "lab/triaxial_settings.hpp"

namespace geodem {

nlohmann::json run_triaxial(const TriaxialSettings& settings, const RunOptions& options);

}  // namespace geodem
