// Building a scene's world from Python (docs/python.md): walls, clumps, random clouds, spar
// chains and bonds added to a scene, each given as a dict with the keys of its TOML table
// ([[walls]], [[clumps]], [[clouds]], [[chains]]) and read by the same readers, so that it
// meets the same checks and errors name the same keys.
#include "builder_binding.hpp"

#include <pybind11/stl.h>

#include <set>

#include "base/error.hpp"
#include "base/random.hpp"
#include "contacts/bonds.hpp"
#include "dict_to_toml.hpp"
#include "io/toml_reader.hpp"
#include "scene/build_scene.hpp"
#include "scene/scene_part_readers.hpp"
#include "scene_binding.hpp"
#include "world/step.hpp"
#include "world/world_editing.hpp"

namespace geodem::python {

namespace {

// The names and templates the part readers check against: the scene's own.
ScenePartContext context_of(const SceneSettings& s) {
  ScenePartContext c;
  c.dimension = s.dimension;
  for (const auto& m : s.materials) c.materials.insert(m.name);
  c.default_material = s.materials.front().name;
  c.templates = &s.templates;
  return c;
}

// A dict, or a list of dicts, as TOML tables; `what` names them in errors ("walls" gives
// walls.0, walls.1 ...).
std::vector<toml::table> tables_of(py::handle spec, const std::string& what) {
  std::vector<toml::table> out;
  if (py::isinstance<py::dict>(spec)) {
    out.push_back(to_table(spec.cast<py::dict>(), what));
  } else if (py::isinstance<py::list>(spec) || py::isinstance<py::tuple>(spec)) {
    for (auto item : spec) {
      if (!py::isinstance<py::dict>(item))
        throw InputError("<dict>", 0, what, "expected a dict or a list of dicts");
      out.push_back(to_table(item.cast<py::dict>(), what + "." + std::to_string(out.size())));
    }
  } else {
    throw InputError("<dict>", 0, what, "expected a dict or a list of dicts");
  }
  return out;
}

// Reads each table of `spec` with read(TableReader&), rejecting keys it did not read.
template <class Read>
void read_each(py::handle spec, const std::string& what, Read&& read) {
  const auto tables = tables_of(spec, what);
  for (std::size_t k = 0; k < tables.size(); ++k) {
    TableReader t(tables[k], tables.size() == 1 ? what : what + "." + std::to_string(k), "<dict>",
                  nullptr);
    read(t);
    t.finish();
  }
}

template <int D>
void bind_builder(py::module_& m, const char* name) {
  using S = Scene<D>;
  auto cls = py::reinterpret_borrow<py::class_<S>>(m.attr(name));
  cls.def(
         "add_walls",
         [](S& s, py::handle spec) {
           auto& w = s.world();
           const ScenePartContext c = context_of(s.settings());
           std::vector<WallSpec> specs;
           std::set<std::string> names;
           for (const auto& wall : w.walls) names.insert(wall.name);
           read_each(spec, "walls", [&](TableReader& t) {
             specs.push_back(read_wall(t, c, w.walls.size() + specs.size()));
             for (const auto& wall : walls_of<D>(specs.back(), s.settings().materials))
               if (names.count(wall.name))
                 t.fail("name", "a wall named '" + wall.name + "' is there already");
             names.insert(specs.back().name);
           });
           std::vector<std::string> added;
           for (const auto& sp : specs)
             for (const auto& wall : walls_of<D>(sp, s.settings().materials)) {
               add_wall(w, wall);
               added.push_back(wall.name);
             }
           return added;
         },
         py::arg("spec"),
         "Adds walls given as a dict (or a list of dicts) with the keys of [[walls]]: name, "
         "type, point, normal, from, to, points, closed, material, velocity, area. Returns "
         "the new walls' names (a polyline has one per segment).")
      .def(
          "add_clumps",
          [](S& s, py::handle spec) {
            auto& w = s.world();
            const ScenePartContext c = context_of(s.settings());
            std::vector<ClumpSpec> specs;
            read_each(spec, "clumps", [&](TableReader& t) { specs.push_back(read_clump(t, c)); });
            for (const auto& sp : specs) add_clump_spec<D>(sp, s.settings(), w);
            update_timestep(w);
            return specs.size();
          },
          py::arg("spec"),
          "Adds clumps given as a dict (or a list of dicts) with the keys of [[clumps]]: "
          "template (built-in or of the scenario's [[templates]]), position, velocity, scale, "
          "angle_deg, axis (3D), material. Placed as given; returns how many.")
      .def(
          "add_cloud",
          [](S& s, py::handle spec) {
            auto& w = s.world();
            const ScenePartContext c = context_of(s.settings());
            std::vector<CloudSpec> specs;
            read_each(spec, "clouds", [&](TableReader& t) { specs.push_back(read_cloud(t, c)); });
            std::vector<Sphere<D>> placed = spheres_of<D>(w.particles);
            const std::size_t before = w.particles.size();
            // A stream of its own per call, so that two clouds do not repeat each other (the
            // first one the scenario's own when it has no clouds: the same grains).
            Random rng(s.settings().seed + 104729 * s.clouds_added++);
            for (std::size_t k = 0; k < specs.size(); ++k)
              add_cloud(s.settings(), specs[k], "clouds." + std::to_string(k), w, rng, placed);
            w.rebuild_needed = true;
            update_timestep(w);
            return w.particles.size() - before;
          },
          py::arg("spec"),
          "Adds grains (or clumps) at random in a box, clear of the grains there, given as a "
          "dict with the keys of [[clouds]]: grain, min, max, count, radius or porosity, "
          "radius_fuzz, velocity, material. Returns how many grains were added.")
      .def(
          "add_chain",
          [](S& s, py::handle spec) {
            auto& w = s.world();
            const ScenePartContext c = context_of(s.settings());
            std::vector<ChainSpec> specs;
            read_each(spec, "chains", [&](TableReader& t) {
              specs.push_back(read_chain(t, c, w.spars.chains.size() + specs.size()));
              for (const auto& chain : w.spars.chains)
                if (chain.name == specs.back().name)
                  t.fail("name", "a chain named '" + chain.name + "' is there already");
            });
            std::vector<std::string> added;
            for (const auto& sp : specs) {
              add_chain_spec<D>(sp, s.settings(), w);
              added.push_back(sp.name);
            }
            update_timestep(w);
            return added;
          },
          py::arg("spec"),
          "Adds spar chains (geosynthetic sheets, cables) given as a dict (or a list of "
          "dicts) with the keys of [[chains]]: name, points, element_length, stiffness_J, "
          "mass_per_length, thickness, bending_stiffness (2D), held, velocity, material. "
          "Returns their names.")
      .def(
          "create_bonds",
          [](S& s, double gap_tolerance) {
            auto& w = s.world();
            bool cohesive = false;
            for (const auto& law : w.pair_laws) cohesive |= law.cohesive();
            if (!cohesive)
              throw InputError("<dict>", 0, "materials",
                               "no pair law is cohesive: give a material normal_cohesion or "
                               "shear_cohesion before creating bonds");
            return create_bonds(w, gap_tolerance);
          },
          py::arg("gap_tolerance") = 0.0,
          "Bonds every pair of grains touching (or closer than gap_tolerance times the "
          "smaller radius) whose pair law is cohesive, as [bonds] create = \"initial\" does. "
          "Returns how many bonds were made.");
}

}  // namespace

void bind_builders(py::module_& m) {
  bind_builder<2>(m, "Scene2D");
  bind_builder<3>(m, "Scene3D");
}

}  // namespace geodem::python
