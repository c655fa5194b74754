#include "io/material_file.hpp"

#include <filesystem>
#include <sstream>

#include "base/error.hpp"
#include "base/text.hpp"
#include "io/output_files.hpp"
#include "io/toml_reader.hpp"
#include "scene/scene_settings.hpp"

#ifndef GEODEM_PRESET_DIR
#define GEODEM_PRESET_DIR "presets"
#endif

namespace geodem {

namespace fs = std::filesystem;

std::string preset_dir() {
  return GEODEM_PRESET_DIR;
}

void write_material_file(const std::string& path, const MaterialFile& m) {
  std::ostringstream t;
  t << "# geodem material \"" << m.name << "\" (" << m.dimension << "D)";
  if (!m.source.empty()) t << ", calibrated by " << m.source;
  t << "\n# Use it in a scenario: [material] file = \"<this file>\" (or [soil] in a pull-out).\n"
    << "name = \"" << m.name << "\"\ndimension = " << m.dimension << "\n\n[material]\n";
  for (const auto& [k, v] : m.material.items())
    t << k << " = " << format_number(v.get<double>()) << "\n";
  t << "\n[grain]\n";
  if (!m.grain.empty()) t << "shape = \"" << m.grain << "\"\n";
  t << "radius_fuzz = " << format_number(m.radius_fuzz) << "\n";
  if (m.porosity > 0.0) t << "porosity = " << format_number(m.porosity) << "\n";
  if (m.interface.is_object()) {
    t << "\n# The soil-sheet interface: the sheet's local friction, and the macroscopic friction\n"
      << "# and adhesion interface shear tests measure with it (the sheet_* keys say which\n"
      << "# sheet; they are not read back).\n[interface]\n";
    for (const auto& [k, v] : m.interface.items())
      t << k << " = " << format_number(v.get<double>()) << "\n";
  }
  t << "\n# Measured on the verification samples (not read back).\n[macro]\n";
  for (const auto& [k, v] : m.macro.items()) {
    if (v.is_array()) {
      t << k << " = [";
      for (std::size_t i = 0; i < v.size(); ++i)
        t << (i ? ", " : "") << format_number(v[i].get<double>());
      t << "]\n";
    } else {
      t << k << " = " << format_number(v.get<double>()) << "\n";
    }
  }
  write_file_atomic(path, t.str());
}

namespace {

// Inserts `value` under `key` of `into` unless the scenario gives it already.
void give_default(toml::table& into, const std::string& key, const toml::node& value) {
  if (!into.contains(key)) into.insert(key, value);
}

toml::table& table_of(toml::table& root, const char* name) {
  if (!root[name].is_table()) root.insert_or_assign(name, toml::table{});
  return *root[name].as_table();
}

// A calibrated interface: the sheet takes the local friction unless the scenario sets its
// own; the pull-out's design estimate then takes the macroscopic friction and adhesion
// measured with it (with a local friction of the scenario's own they do not apply).
void expand_interface(toml::table& root, const toml::table& itf, const std::string& kind) {
  const toml::node* local = itf.get("local_friction_deg");
  if (!local) return;
  toml::table& sheet = table_of(root, "sheet");
  if (sheet.contains("interface_friction_deg")) return;
  sheet.insert("interface_friction_deg", *local);
  if (kind != "pullout") return;
  toml::table& analytic = table_of(root, "analytic");
  if (const toml::node* macro = itf.get("macro_friction_deg"))
    give_default(analytic, "interface_friction_deg", *macro);
  if (const toml::node* adhesion = itf.get("macro_adhesion"))
    give_default(analytic, "interface_adhesion", *adhesion);
}

}  // namespace

void expand_material_reference(toml::table& root, const std::string& kind,
                               const std::string& scenario_file) {
  // The 2D kinds over a deposited soil name their material [soil].
  const bool soil_kind = kind == "pullout" || kind == "interface_shear";
  const std::string table_name = soil_kind ? "soil" : "material";
  toml::table* mat = root[table_name].as_table();
  if (!mat || !(mat->contains("preset") || mat->contains("file"))) return;
  const std::string where = cat(table_name, ".");
  auto line = [&](const char* key) {
    return static_cast<int>((*mat)[key].node()->source().begin.line);
  };
  if (mat->contains("preset") && mat->contains("file"))
    throw InputError(scenario_file, line("file"), cat(where, "file"),
                     "give either 'preset' or 'file', not both");
  const char* key = mat->contains("preset") ? "preset" : "file";
  const auto name = (*mat)[key].value<std::string>();
  if (!name) throw InputError(scenario_file, line(key), cat(where, key), "expected a string");
  fs::path path;
  std::error_code exists_error;  // a name the system cannot take is not found, not a crash
  if (std::string(key) == "preset") {
    path = fs::path(preset_dir()) / cat(*name, ".toml");
    const bool plain = !name->empty() && name->find_first_of("/\\") == std::string::npos;
    if (!plain || !fs::is_regular_file(path, exists_error)) {
      std::string known;
      std::error_code ec;
      for (const auto& e : fs::directory_iterator(preset_dir(), ec))
        if (e.path().extension() == ".toml") known = cat(known, " ", e.path().stem().string());
      throw InputError(scenario_file, line(key), cat(where, key),
                       cat("unknown preset \"", *name, "\"; shipped presets:", known));
    }
  } else {
    path = fs::path(*name);
    if (path.is_relative()) path = fs::path(scenario_file).parent_path() / path;
    if (!fs::is_regular_file(path, exists_error))
      throw InputError(scenario_file, line(key), cat(where, key),
                       cat("material file ", path.string(), " not found"));
  }
  const int ref_line = line(key);
  mat->erase(key);
  const toml::table file = parse_toml_file(path.string());
  const std::string f = path.string();
  // The scenario's dimension must be the material's.
  const long long dim = file["dimension"].value_or(0LL);
  const long long want = soil_kind ? 2 : root["dimension"].value_or(3LL);
  if (dim != want)
    throw InputError(
        scenario_file, ref_line, cat(where, key),
        cat("material ", f, " is for dimension ", dim, ", the scenario is ", want, "D"));
  const toml::table* m = file["material"].as_table();
  if (!m) throw InputError(f, 0, "material", "missing [material] table");
  {
    // Checked here, where errors can name the material file and its lines: copies of
    // TOML nodes lose their source position.
    TableReader r(*m, "material", f, nullptr);
    read_material(r, "check");
    r.finish();
  }
  for (const auto& [k, v] : *m) {
    // A friction coefficient in the scenario overrides the file's angle.
    if (k.str() == "friction_deg" && mat->contains("friction")) continue;
    give_default(*mat, std::string(k.str()), v);
  }
  if (const toml::table* itf = file["interface"].as_table(); itf && soil_kind)
    expand_interface(root, *itf, kind);
  const toml::table* grain = file["grain"].as_table();
  if (!grain) return;
  toml::table* shape_table = soil_kind ? mat : root["sample"].as_table();
  if (shape_table && !shape_table->contains("grains")) {
    if (const toml::node* shape = grain->get("shape")) give_default(*shape_table, "grain", *shape);
    if (const toml::node* fuzz = grain->get("radius_fuzz"))
      give_default(*shape_table, "radius_fuzz", *fuzz);
  }
  if (!soil_kind) {
    if (const toml::node* porosity = grain->get("porosity"))
      if (toml::table* c = root["compaction"].as_table())
        give_default(*c, "target_porosity", *porosity);
  }
}

}  // namespace geodem
