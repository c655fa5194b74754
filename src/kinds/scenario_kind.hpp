// The table of scenario kinds: what `geodem check` and `geodem run` do with each `kind`. The
// command line (and any other front end) looks a kind up here and calls its entry; adding a
// kind is adding one entry (docs/architecture.md, "Add a scenario kind").
#pragma once

#include <toml++/toml.h>
#include <string>
#include <vector>

#include "clumps/grain_mix.hpp"
#include "io/plot_process.hpp"
#include "io/run_output.hpp"
#include "io/scenario_file.hpp"

namespace geodem {

// What a run reports back: its exit code (0, or 1/3 when some of a study's runs failed) and
// the line the command line prints at the end ("done: ...; outputs in DIR").
struct KindRun {
  int exit_code = 0;
  std::string done;
};

struct ScenarioKind {
  const char* name;
  // The kind whose material tables a material file reference fills ([material] of a lab test,
  // [soil] of a pull-out...); nullptr: the kind itself (io/material_file.hpp).
  const char* (*materials_as)(const toml::table& root);
  // Continued by --resume from its output folder (checkpoints, or a study's finished runs).
  bool resumable;
  // Its runs are shared across MPI ranks (studies; a pull-out over seeds or grain sizes).
  bool (*shares_ranks)(const toml::table& root);
  // Reads every key as a run would and refuses a run that would not fit in memory (`threads`:
  // a study's runs side by side); `build`: also builds what is cheap to build (a scene's
  // grains, whose clouds may not fit). Returns what `geodem check` reports of a sound one.
  std::string (*check)(const toml::table& root, const std::string& file, int threads, bool build);
  // Runs it: claims the output folder (refusal, --overwrite), writes the outputs, draws the
  // plots the scenario asks for.
  KindRun (*run)(const LoadedScenario& scenario, const std::string& file, const RunOptions& options,
                 bool overwrite);
  // One run of it spreads its world over the ranks of mpirun (docs/parallel.md).
  bool decomposes = false;
};

// Every kind, in the order the docs list them.
const std::vector<ScenarioKind>& scenario_kinds();

// The scenario's kind; an InputError naming the file, the line of `kind` and the known kinds
// when there is none of that name.
const ScenarioKind& find_kind(const LoadedScenario& scenario, const std::string& file);

// Reads a scenario file (io/scenario_file.hpp) whose kind must be one of the table's.
LoadedScenario load_known_scenario(const std::string& file,
                                   const std::vector<std::string>& overrides);
// The same from text already in memory; `name` stands for the file in messages.
LoadedScenario load_known_scenario_text(const std::string& text, const std::string& name);
LoadedScenario load_known_scenario_table(toml::table root, const std::string& name);

// Claims a new run's output folder (io/run_output.hpp, claim_output_dir): rank 0 decides,
// and empties it on --overwrite, before any rank writes into it. Nothing on a resume.
void claim_output(const RunOptions& options, bool overwrite);

// Grains in memory for the memory estimate: discs or spheres per grain of a grain mix (its
// largest clump), and discs of radius r that a dense 2D deposit puts in an area.
double members_per_grain(const GrainSpec& spec, int dimension);
double discs_in(double area, double r);

// The entries, one file per family.
ScenarioKind scene_kind();
ScenarioKind triaxial_kind();
ScenarioKind isotropic_kind();
ScenarioKind oedometer_kind();
ScenarioKind simple_shear_kind();
ScenarioKind cyclic_triaxial_kind();
ScenarioKind direct_shear_kind();
ScenarioKind pullout_kind();
ScenarioKind interface_shear_kind();
ScenarioKind series_kind();
ScenarioKind rate_study_kind();
ScenarioKind calibrate_kind();

}  // namespace geodem
