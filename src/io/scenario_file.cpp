#include "io/scenario_file.hpp"

#include "base/error.hpp"
#include "io/toml_reader.hpp"

namespace geodem {

namespace {

LoadedScenario finish_loading(toml::table root, const std::vector<std::string>& overrides,
                              const std::string& file) {
  LoadedScenario l{std::move(root), "", 1};
  for (const auto& o : overrides) apply_override(l.root, o, file);
  const toml::node* kind = l.root.get("kind");
  if (!kind) throw InputError(file, 1, "kind", "missing; expected kind = \"scene\"");
  l.kind_line = static_cast<int>(kind->source().begin.line);
  if (!kind->is_string()) throw InputError(file, l.kind_line, "kind", "expected a string");
  l.kind = *kind->value<std::string>();
  return l;
}

}  // namespace

LoadedScenario load_scenario(const std::string& file, const std::vector<std::string>& overrides) {
  return finish_loading(parse_toml_file(file), overrides, file);
}

LoadedScenario load_scenario_text(const std::string& text, const std::string& name) {
  return finish_loading(parse_toml_text(text, name), {}, name);
}

LoadedScenario load_scenario_table(toml::table root, const std::string& name) {
  return finish_loading(std::move(root), {}, name);
}

}  // namespace geodem
