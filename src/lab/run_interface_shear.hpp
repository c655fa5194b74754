// Runs a `kind = "interface_shear"` scenario and writes its output folder.
#pragma once

#include <nlohmann/json.hpp>

#include "io/run_output.hpp"
#include "lab/interface_shear_settings.hpp"

namespace geodem {

nlohmann::json run_interface_shear(const InterfaceShearSettings& settings,
                                   const RunOptions& options);

}  // namespace geodem
