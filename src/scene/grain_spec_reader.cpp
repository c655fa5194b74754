#include "scene/grain_spec_reader.hpp"

#include <algorithm>

namespace geodem {

std::vector<TemplateSpec> read_templates(TableReader& root, int dimension) {
  std::vector<TemplateSpec> out;
  const std::size_t row = static_cast<std::size_t>(dimension) + 1;
  for (auto& t : root.tables("templates")) {
    TemplateSpec ts;
    ts.name = t.string("name", "");
    if (ts.name.empty()) t.fail("name", "a template needs a name");
    if (is_round_shape(ts.name)) t.fail("name", "'" + ts.name + "' is the round grain's name");
    ts.members = t.number_rows("members", row);
    if (ts.members.empty())
      t.fail("members", "expected rows [x, y," + std::string(dimension == 3 ? " z," : "") +
                            " radius] (one per member)");
    for (const auto& m : ts.members)
      if (!(m.back() > 0.0)) t.fail("members", "member radii must be positive");
    t.finish();
    out.push_back(ts);
  }
  return out;
}

void check_shape(TableReader& t, const std::string& key, const std::string& shape,
                 const std::vector<TemplateSpec>& templates) {
  std::vector<std::string> known = builtin_clump_template_names();
  for (const auto& k : templates) known.push_back(k.name);
  if (std::find(known.begin(), known.end(), shape) != known.end()) return;
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  t.fail(key, "unknown grain '" + shape + "'; expected one of: " + list);
}

GrainSpec read_grain_spec(TableReader& sample, int dimension,
                          const std::vector<TemplateSpec>& templates) {
  GrainSpec spec;
  spec.templates = templates;
  auto mix = sample.tables("grains");
  if (!mix.empty()) {
    if (sample.has("grain")) sample.fail("grain", "give either 'grain' or [[...grains]], not both");
    spec.kinds.clear();
    for (auto& t : mix) {
      GrainKind k;
      k.shape = t.string("shape", dimension == 3 ? "sphere" : "disc");
      check_shape(t, "shape", k.shape, templates);
      k.size = t.positive("size", 1.0);
      k.fraction = t.positive("fraction", 1.0);
      t.finish();
      spec.kinds.push_back(k);
    }
  } else {
    spec.kinds[0].shape = sample.string("grain", dimension == 3 ? "sphere" : "disc");
    check_shape(sample, "grain", spec.kinds[0].shape, templates);
  }
  return spec;
}

}  // namespace geodem
