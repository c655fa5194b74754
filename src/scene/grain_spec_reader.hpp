// The grain kinds of a scenario: `[[templates]]`, `grain = "<shape>"` or `[[...grains]]`,
// read into the engine's GrainSpec (clumps/grain_mix.hpp).
#pragma once

#include <string>
#include <vector>

#include "clumps/grain_mix.hpp"
#include "io/toml_reader.hpp"

namespace geodem {

// Reads the `[[templates]]` (name, members) of the root table.
std::vector<TemplateSpec> read_templates(TableReader& root, int dimension);

// Checks that `shape` names a round grain, a built-in template or one of `templates`.
void check_shape(TableReader& t, const std::string& key, const std::string& shape,
                 const std::vector<TemplateSpec>& templates);

// Reads `grain = "<shape>"` or `[[<table>.grains]]` (shape, size, fraction) from `sample`.
GrainSpec read_grain_spec(TableReader& sample, int dimension,
                          const std::vector<TemplateSpec>& templates);

}  // namespace geodem
