// A scenario file read up to its kind: TOML parsed, --set overrides applied, material
// file references expanded. Each kind's reader (scene/, lab/, study/) checks the rest.
#pragma once

#include <toml++/toml.h>
#include <string>
#include <vector>

namespace geodem {

struct LoadedScenario {
  toml::table root;
  std::string kind;  // one of scenario_kinds()
};

const std::vector<std::string>& scenario_kinds();

// Throws InputError (file, line, key, what was expected) on any defect.
LoadedScenario load_scenario(const std::string& file, const std::vector<std::string>& overrides);

// The same from text already in memory; `name` stands for the file in messages.
LoadedScenario load_scenario_text(const std::string& text, const std::string& name);

// Runs the reader of the scenario's kind: every key checked, nothing built or run.
void check_scenario_settings(const LoadedScenario& scenario, const std::string& file);

}  // namespace geodem
