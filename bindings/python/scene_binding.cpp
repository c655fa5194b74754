#include "scene_binding.hpp"

#include "contacts_binding.hpp"

#include <pybind11/stl.h>

#include <limits>

#include <filesystem>

#include "base/error.hpp"
#include "contacts/bonds.hpp"
#include "io/checkpoint.hpp"
#include "measure/contact_network.hpp"
#include "measure/displacement.hpp"
#include "measure/measurements.hpp"
#include "scene/build_scene.hpp"
#include "scene/input_overlaps.hpp"
#include "scene/scene_start.hpp"
#include "world/step.hpp"
#include "world/world_editing.hpp"
#include "world/world_state.hpp"

namespace geodem::python {

template <int D>
Scene<D>::Scene(SceneSettings settings) : settings_(std::move(settings)) {
  build_world<D>(settings_, world_);
  if (!settings_.start_checkpoint.empty()) start_from_checkpoint(settings_, world_);
  world_.particles.stable_buffers = true;  // the numpy views stay valid across steps
  clouds_added = settings_.clouds.empty() ? 0 : 1;
  if (settings_.bonds_initial) create_bonds(world_, settings_.bond_gap_tolerance);
  update_timestep(world_);  // as the command line's scene runner does before its first step
}

template <int D>
void Scene<D>::step(std::uint64_t n) {
  py::gil_scoped_release release;
  for (std::uint64_t k = 0; k < n; ++k) {
    world_.measure_this_step = k + 1 == n;
    geodem::step(world_);
  }
}

template <int D>
void Scene<D>::run(py::object self, std::uint64_t steps, double until, std::uint64_t every,
                   py::object callback) {
  if (every == 0) throw InputError("", 0, "every", "must be at least 1");
  const std::uint64_t end =
      steps > 0 ? world_.step + steps : std::numeric_limits<std::uint64_t>::max();
  while (world_.step < end && world_.time < until) {
    const std::uint64_t n = std::min<std::uint64_t>(every, end - world_.step);
    step(n);
    if (!callback.is_none()) {
      const py::object go = callback(self);
      if (!go.is_none() && !go.cast<bool>()) break;
    }
  }
}

template <int D>
std::size_t Scene<D>::wall_index(const std::string& name) const {
  for (std::size_t k = 0; k < world_.walls.size(); ++k)
    if (world_.walls[k].name == name) return k;
  std::string known;
  for (const auto& w : world_.walls) known += (known.empty() ? "" : ", ") + w.name;
  throw py::key_error("no wall '" + name + "'; the walls are: " + known);
}

template <int D>
std::string Scene<D>::write_vtk(const std::string& folder, bool contacts) {
  if (!vtk_ || folder != vtk_folder_) {
    std::filesystem::create_directories(std::filesystem::path(folder) / "vtk");
    vtk_ = std::make_shared<VtkSeries<D>>(folder);
    vtk_folder_ = folder;
  }
  vtk_->with_contacts(contacts);
  vtk_->with_reference(reference.empty() ? nullptr : &reference);
  vtk_->write(world_);
  return folder + "/vtk/particles.pvd";
}

template <int D>
void Scene<D>::save(const std::string& path) const {
  Checkpoint c;
  c.kind = "scene";
  c.dimension = D;
  c.step = world_.step;
  c.time = world_.time;
  c.scenario = settings_.resolved.dump();
  write_checkpoint_file(path, c, [this](StateWriter& out) { save_world_state(out, world_); });
}

template <int D>
void Scene<D>::load_state(const std::string& archive) {
  StateReader in(archive.data(), archive.size());
  load_world_state_with_walls(in, world_);
  world_.controllers.clear();
}

namespace {

// A read-only numpy view of an array of fixed-size Eigen vectors (or of doubles): no copy; it
// keeps the scene alive, and is valid until the next step (a rebuild may renumber the grains,
// or the arrays may move).
template <typename T>
py::array view(const std::vector<T>& v, int columns, py::handle owner) {
  const auto n = static_cast<py::ssize_t>(v.size());
  py::array a = columns == 0 ? py::array(py::dtype::of<double>(), {n}, {sizeof(T)},
                                         reinterpret_cast<const double*>(v.data()), owner)
                             : py::array(py::dtype::of<double>(), {n, py::ssize_t{columns}},
                                         {py::ssize_t{sizeof(T)}, py::ssize_t{sizeof(double)}},
                                         reinterpret_cast<const double*>(v.data()), owner);
  a.attr("flags").attr("writeable") = false;
  return a;
}

template <int D>
void bind(py::module_& m, const char* name) {
  using S = Scene<D>;
  using Vec = typename Dim<D>::Vec;
  static_assert(sizeof(Vec) == D * sizeof(double), "grain vectors are packed doubles");
  py::class_<S>(m, name)
      .def("step", &S::step, py::arg("n") = 1, "Advances n time steps (the GIL is released).")
      .def(
          "run",
          [](py::object self, std::uint64_t steps, double until, std::uint64_t every,
             py::object callback) {
            self.cast<S&>().run(self, steps, until, every, std::move(callback));
          },
          py::arg("steps") = 0, py::arg("until") = std::numeric_limits<double>::infinity(),
          py::arg("every") = 100, py::arg("callback") = py::none(),
          "Steps until `steps` more steps or the time `until`, calling callback(scene) every "
          "`every` steps; a callback returning False stops.")
      .def_property_readonly("dimension", [](const S&) { return D; })
      .def_property_readonly("time", [](S& s) { return s.world().time; })
      .def_property_readonly("steps", [](S& s) { return s.world().step; })
      .def_property_readonly("dt", [](S& s) { return s.world().dt; })
      .def_property(
          "threads", [](S& s) { return s.world().threads; },
          [](S& s, int t) {
            if (t < 1) throw py::value_error("threads must be at least 1");
            s.world().threads = t;
          })
      .def_property_readonly("count", [](S& s) { return s.world().particles.size(); })
      .def_property_readonly(
          "positions",
          [](py::object self) { return view(self.cast<S&>().world().particles.pos, D, self); })
      .def_property_readonly(
          "velocities",
          [](py::object self) { return view(self.cast<S&>().world().particles.vel, D, self); })
      .def_property_readonly(
          "forces",
          [](py::object self) { return view(self.cast<S&>().world().particles.force, D, self); })
      .def_property_readonly(
          "radii",
          [](py::object self) { return view(self.cast<S&>().world().particles.radius, 0, self); })
      .def_property_readonly("spins",
                             [](py::object self) {
                               return view(self.cast<S&>().world().particles.angvel, D == 2 ? 0 : 3,
                                           self);
                             })
      .def_property_readonly("masses",
                             [](S& s) {
                               const auto& inv = s.world().particles.inv_mass;
                               py::array_t<double> mass(static_cast<py::ssize_t>(inv.size()));
                               for (std::size_t i = 0; i < inv.size(); ++i)
                                 mass.mutable_data()[i] = 1.0 / inv[i];  // inf: a fixed grain
                               return mass;
                             })
      .def_property_readonly("clump_ids",
                             [](S& s) {
                               const auto& P = s.world().particles;
                               py::array_t<std::int64_t> c(static_cast<py::ssize_t>(P.size()));
                               for (std::size_t i = 0; i < P.size(); ++i)
                                 c.mutable_data()[i] = P.clump.empty() || P.clump[i] == kNoClump
                                                           ? -1
                                                           : static_cast<std::int64_t>(P.clump[i]);
                               return c;
                             })
      .def_property_readonly("ids",
                             [](S& s) {
                               const auto& id = s.world().particles.id;
                               return py::array_t<std::uint32_t>(
                                   static_cast<py::ssize_t>(id.size()), id.data());
                             })
      .def(
          "wall_contacts", [](S& s) { return wall_contact_arrays(s.world()); },
          "The grain-wall contacts at the last step as arrays (copies): grain, wall (an index "
          "of walls), normal (from the grain to the wall), overlap, normal_force (elastic "
          "part, on the wall), tangential_force (on the wall).")
      .def(
          "contacts", [](S& s) { return contact_arrays(s.world()); },
          "The grain-grain contacts at the last step as arrays (copies): i, j, normal (from i to "
          "j), overlap, normal_force (the law's elastic part), tangential_force (on j), bonded.")
      .def("kinetic_energy", [](S& s) { return kinetic_energy(s.world()); })
      .def("unbalanced_force", [](S& s) { return unbalanced_force_ratio(s.world()); })
      .def("coordination", [](S& s) { return coordination_number(s.world()); })
      .def_property_readonly("walls",
                             [](S& s) {
                               py::list names;
                               for (const auto& w : s.world().walls) names.append(w.name);
                               return names;
                             })
      .def(
          "wall_force",
          [](S& s, const std::string& wall) {
            const Vec f = s.world().walls[s.wall_index(wall)].force;
            return py::array_t<double>(D, f.data());
          },
          "The force the grains exert on the wall at the last step (N; N/m in 2D).")
      .def(
          "wall_stiffness",
          [](S& s, const std::string& wall) {
            return s.world().walls[s.wall_index(wall)].stiffness;
          },
          "The sum of the normal stiffnesses of the wall's contacts at the last step (N/m; N/m "
          "per m in 2D): what a servo divides a force error by.")
      .def(
          "wall_point",
          [](S& s, const std::string& wall) {
            const Vec p = s.world().walls[s.wall_index(wall)].point;
            return py::array_t<double>(D, p.data());
          },
          "A point of the wall (a plane's point, a segment's first end).")
      .def(
          "set_wall_velocity",
          [](S& s, const std::string& wall, const std::vector<double>& v) {
            if (v.size() != static_cast<std::size_t>(D))
              throw py::value_error("a velocity has " + std::to_string(D) + " components");
            auto& w = s.world().walls[s.wall_index(wall)];
            for (int k = 0; k < D; ++k) w.velocity[k] = v[static_cast<std::size_t>(k)];
          },
          "Moves the wall at this velocity (m/s) from the next step on.")
      .def(
          "remove_wall",
          [](S& s, const std::string& wall) { remove_wall(s.world(), s.wall_index(wall)); },
          "Removes the wall; the other walls keep their contacts.")
      .def(
          "set_friction",
          [](S& s, double mu) {
            if (!(mu >= 0.0)) throw py::value_error("friction must be a coefficient >= 0");
            set_friction(s.world(), mu);
          },
          "Sets the friction coefficient of every contact (grain-grain, grain-wall, "
          "grain-chain); springs above the new Coulomb limit slide back to it at the next "
          "step.")
      .def(
          "set_gravity",
          [](S& s, const std::vector<double>& g) {
            if (g.size() != static_cast<std::size_t>(D))
              throw py::value_error("gravity has " + std::to_string(D) + " components");
            for (int k = 0; k < D; ++k) s.world().gravity[k] = g[static_cast<std::size_t>(k)];
          },
          "Sets the gravity vector (m/s^2).")
      .def(
          "remove_grains",
          [](S& s, py::array_t<bool, py::array::c_style | py::array::forcecast> mask) {
            auto& w = s.world();
            if (mask.ndim() != 1 || static_cast<std::size_t>(mask.shape(0)) != w.particles.size())
              throw py::value_error("expected a boolean mask with one entry per grain (" +
                                    std::to_string(w.particles.size()) + ")");
            std::vector<char> remove(w.particles.size());
            for (std::size_t i = 0; i < remove.size(); ++i) remove[i] = mask.data()[i];
            const std::size_t n = remove_grains(w, remove, ContactHistory::kKeep);
            update_timestep(w);
            return n;
          },
          py::arg("mask"),
          "Removes the grains where mask is True (whole clumps when a member is); the others "
          "keep their contacts. Returns how many grains left. Views taken before are stale.")
      .def(
          "add_grains",
          [](S& s, py::array_t<double, py::array::c_style | py::array::forcecast> positions,
             py::array_t<double, py::array::c_style | py::array::forcecast> radii,
             py::object velocities, const std::string& material) {
            auto& w = s.world();
            const auto n = positions.ndim() == 2 ? positions.shape(0) : -1;
            if (n < 0 || positions.shape(1) != D)
              throw py::value_error("positions: expected an array of shape (N, " +
                                    std::to_string(D) + ")");
            if (radii.ndim() != 1 || radii.shape(0) != n)
              throw py::value_error("radii: expected one radius per position");
            py::array_t<double, py::array::c_style | py::array::forcecast> vel;
            if (!velocities.is_none()) {
              vel =
                  velocities.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
              if (vel.ndim() != 2 || vel.shape(0) != n || vel.shape(1) != D)
                throw py::value_error("velocities: expected the shape of positions");
            }
            std::uint16_t mat = 0;
            if (!material.empty()) {
              bool found = false;
              for (std::size_t k = 0; k < w.materials.size(); ++k)
                if (w.materials[k].name == material)
                  mat = static_cast<std::uint16_t>(k), found = true;
              if (!found) throw py::key_error("no material '" + material + "'");
            }
            // Overlaps the step would stop at are an input error naming the grains, as for
            // the scenario's [[particles]].
            std::vector<Sphere<D>> all = spheres_of<D>(w.particles);
            const std::size_t before = w.particles.size();
            for (py::ssize_t i = 0; i < n; ++i) {
              const double r = radii.data()[i];
              if (!(r > 0.0)) throw py::value_error("radii must be positive");
              Vec x;
              for (int k = 0; k < D; ++k) x[k] = positions.data()[i * D + k];
              all.push_back({x, r});
            }
            reject_input_overlaps<D>(
                all,
                [&](std::size_t k) {
                  return k < before ? "the grain of id " + std::to_string(w.particles.id[k])
                                    : "positions[" + std::to_string(k - before) + "]";
                },
                w.overlap_limit, "<python>");
            for (py::ssize_t i = 0; i < n; ++i) {
              Vec v = Vec::Zero();
              for (int k = 0; k < D && !velocities.is_none(); ++k) v[k] = vel.data()[i * D + k];
              const auto& g = all[w.particles.size()];
              w.particles.add(g.centre, g.radius, w.materials[mat].density, mat, v);
            }
            if (!w.nlist.start.empty()) {  // the new grains start with empty rows
              for (auto* start : {&w.nlist.start, &w.nlist.wall_start, &w.nlist.spar_start})
                if (!start->empty()) start->resize(w.particles.size() + 1, start->back());
            }
            w.rebuild_needed = true;
            update_timestep(w);
            return n;
          },
          py::arg("positions"), py::arg("radii"), py::arg("velocities") = py::none(),
          py::arg("material") = "",
          "Adds grains at the given positions (N, D) with radii (N) and optional velocities, "
          "of a material of the scenario (default: the first). They are placed as given; an "
          "overlap beyond the scene's max_overlap is a geodem.InputError naming the grains. "
          "Returns how many were added.")
      .def(
          "fabric",
          [](S& s) {
            const auto f = fabric_tensor(s.world());
            py::array_t<double> t({py::ssize_t{D}, py::ssize_t{D}});
            for (int a = 0; a < D; ++a)
              for (int b = 0; b < D; ++b) t.mutable_data()[a * D + b] = f(a, b);
            py::dict out;
            out["tensor"] = t;
            out["anisotropy"] = fabric_anisotropy<D>(f);
            return out;
          },
          "The fabric tensor <n n> of the grain-grain contacts (trace 1) and its anisotropy "
          "D (largest - smallest eigenvalue).")
      .def(
          "set_reference", [](S& s) { s.reference = positions_by_id(s.world()); },
          "Takes the grains' current positions as the reference of displacements().")
      .def(
          "displacements",
          [](S& s) {
            if (s.reference.empty())
              throw py::value_error("no reference: call set_reference() first");
            const auto& w = s.world();
            py::array_t<double> a({static_cast<py::ssize_t>(w.particles.size()), py::ssize_t{D}});
            double* out = a.mutable_data();
            for (std::size_t i = 0; i < w.particles.size(); ++i) {
              const Vec d = displacement(w, s.reference, i);
              for (int k = 0; k < D; ++k) *out++ = d[k];
            }
            return a;
          },
          "Each grain's displacement since set_reference() (N, D), in the order of positions; "
          "NaN for grains added since.")
      .def("write_vtk", &S::write_vtk, py::arg("folder"), py::arg("contacts") = true,
           "Appends a frame to the VTK series in folder/vtk (grains, walls, chains, and the "
           "contact network as lines); returns the .pvd index's path.")
      .def("save", &S::save, py::arg("path"),
           "Writes a checkpoint file of the scene: geodem.load(path) gives it back, bit for "
           "bit.");
}

}  // namespace

void bind_scenes(py::module_& m) {
  bind<2>(m, "Scene2D");
  bind<3>(m, "Scene3D");
}

template class Scene<2>;
template class Scene<3>;

}  // namespace geodem::python
