#include <algorithm>

#include "base/error.hpp"
#include "io/material_file.hpp"
#include "kinds/scenario_kind.hpp"
#include "study/study_comm.hpp"

namespace geodem {

const std::vector<ScenarioKind>& scenario_kinds() {
  static const std::vector<ScenarioKind> kinds = {
      scene_kind(),           triaxial_kind(),        isotropic_kind(),    oedometer_kind(),
      simple_shear_kind(),    cyclic_triaxial_kind(), direct_shear_kind(), pullout_kind(),
      interface_shear_kind(), series_kind(),          rate_study_kind(),   calibrate_kind()};
  return kinds;
}

const ScenarioKind& find_kind(const LoadedScenario& l, const std::string& file) {
  const auto& kinds = scenario_kinds();
  const auto it = std::find_if(kinds.begin(), kinds.end(),
                               [&](const ScenarioKind& k) { return l.kind == k.name; });
  if (it != kinds.end()) return *it;
  std::string known;
  for (const auto& k : kinds) known += (known.empty() ? "\"" : ", \"") + std::string(k.name) + "\"";
  throw InputError(file, l.kind_line, "kind",
                   "unknown kind \"" + l.kind + "\"; expected one of " + known);
}

namespace {
// The kind checked and the material file references expanded.
LoadedScenario with_known_kind(LoadedScenario l, const std::string& file) {
  const ScenarioKind& kind = find_kind(l, file);
  expand_material_reference(l.root, kind.materials_as ? kind.materials_as(l.root) : kind.name,
                            file);
  return l;
}
}  // namespace

LoadedScenario load_known_scenario(const std::string& file,
                                   const std::vector<std::string>& overrides) {
  return with_known_kind(load_scenario(file, overrides), file);
}

LoadedScenario load_known_scenario_text(const std::string& text, const std::string& name) {
  return with_known_kind(load_scenario_text(text, name), name);
}

LoadedScenario load_known_scenario_table(toml::table root, const std::string& name) {
  return with_known_kind(load_scenario_table(std::move(root), name), name);
}

void claim_output(const RunOptions& opt, bool overwrite) {
  if (opt.resume) return;
  std::string refusal;
  if (comm::rank() == 0) refusal = claim_output_dir(opt.out_dir, overwrite);
  if (comm::size() > 1) refusal = comm::all_gather(refusal)[0];
  if (!refusal.empty()) throw InputError("", 0, "--out", refusal);
}

namespace {
template <int D>
double members(const GrainSpec& spec) {
  std::size_t m = 1;
  for (const auto& k : resolve_kinds<D>(spec))
    if (!k.round) m = std::max(m, k.clump.radius.size());
  return static_cast<double>(m);
}
}  // namespace

double members_per_grain(const GrainSpec& spec, int dimension) {
  return dimension == 2 ? members<2>(spec) : members<3>(spec);
}

double discs_in(double area, double r) {
  return 0.8 * area / (3.14159265358979 * r * r);  // porosity about 0.2
}

}  // namespace geodem
