// `geodem check`: every problem of a scenario in one pass, not only the first.
//
// The readers stop at the first bad key (an InputError). To find the others, the check
// reads the scenario again without each key found bad (as if the user had deleted that
// line: the reader takes its default, or reports it missing), until it reads through. A
// problem that removing its key cannot clear (a required key that is missing, a whole
// table, a key of another file such as a preset) ends the search: the keys after it are
// then unchecked, and the result says so.
#pragma once

#include <toml++/toml.h>

#include <functional>
#include <string>
#include <vector>

#include "base/error.hpp"

namespace geodem {

struct ScenarioProblems {
  std::vector<InputError> errors;  // sorted by line
  bool complete = true;            // false: the search stopped at a problem it could not clear
};

// Reads `root` with `read` (which throws InputError on a bad key) until it passes or a
// problem cannot be cleared; at most `max_problems`. The keys found bad are removed from
// `root` (in place: a copy of a parsed table loses the source lines the messages give).
ScenarioProblems find_scenario_problems(toml::table& root,
                                        const std::function<void(const toml::table&)>& read,
                                        int max_problems = 100);

// Removes the key at a dotted path ("shear.rate", "walls.0.normal"); false when absent.
bool remove_dotted_key(toml::table& root, const std::string& dotted);

}  // namespace geodem
