// `geodem check SCENARIO`: every problem of the scenario in one pass (io/scenario_check.hpp),
// sorted by line, with their count; a scene's grains are built too (clouds that cannot be
// placed are input errors), and a run that would not fit in memory is one of the problems
// (io/memory_budget.hpp; `threads`: a study's runs side by side). The keys found bad are removed
// from l.root. Returns the exit code: 0 when the scenario is sound, 2 else.
#pragma once

#include <string>

#include "io/scenario_file.hpp"

int check_scenario(geodem::LoadedScenario& l, const std::string& file, int threads);

// Before a run: refuses it (InputError with the estimate) when it would not fit in memory.
void check_run_memory(const geodem::LoadedScenario& l, const std::string& file, int threads);
