// The study kinds (docs/studies.md): each builds its runs from the study file, has a
// StudyExecutor run them (in parallel, resumable, across MPI ranks), analyses the
// results and, on rank 0, writes summary.json, its tables and its plots' data.
#pragma once

#include <nlohmann/json.hpp>

#include "io/run_output.hpp"
#include "lab/pullout_settings.hpp"
#include "study/study_settings.hpp"

namespace geodem {

// Each returns the study's summary (on every rank).
nlohmann::json run_series(const SeriesSettings& settings, const RunOptions& options);
nlohmann::json run_rate_study(const RateStudySettings& settings, const RunOptions& options);
nlohmann::json run_calibrate(const CalibrateSettings& settings, const RunOptions& options);
// A pull-out scenario with seeds > 1 or [refinement]: root is the loaded scenario.
nlohmann::json run_pullout_series(const toml::table& root, const PulloutSettings& settings,
                                  const RunOptions& options);
nlohmann::json run_interface_calibrate(const InterfaceCalibrateSettings& settings,
                                       const RunOptions& options);

}  // namespace geodem
