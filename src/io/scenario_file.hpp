// A scenario file read up to its kind: TOML parsed, --set overrides applied, the `kind`
// string found. The kinds' table (kinds/scenario_kind.hpp) checks the kind, expands the
// material file references and runs the kind's reader.
#pragma once

#include <toml++/toml.h>
#include <string>
#include <vector>

namespace geodem {

struct LoadedScenario {
  toml::table root;
  std::string kind;
  int kind_line = 1;  // the line of `kind` in the file, for messages
};

// Throws InputError (file, line, key, what was expected) on any defect of the TOML, of an
// override or of the `kind` key (missing, not a string).
LoadedScenario load_scenario(const std::string& file, const std::vector<std::string>& overrides);

// The same from text already in memory, or from a table built by other means (the Python
// module's dicts); `name` stands for the file in messages.
LoadedScenario load_scenario_text(const std::string& text, const std::string& name);
LoadedScenario load_scenario_table(toml::table root, const std::string& name);

}  // namespace geodem
