#include "scene_binding.hpp"

#include "contacts_binding.hpp"

#include <pybind11/stl.h>

#include <limits>

#include "base/error.hpp"
#include "contacts/bonds.hpp"
#include "measure/measurements.hpp"
#include "scene/build_scene.hpp"
#include "world/step.hpp"

namespace geodem::python {

template <int D>
Scene<D>::Scene(SceneSettings settings) : settings_(std::move(settings)) {
  build_world<D>(settings_, world_);
  world_.particles.stable_buffers = true;  // the numpy views stay valid across steps
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
      .def_property_readonly("ids",
                             [](S& s) {
                               const auto& id = s.world().particles.id;
                               return py::array_t<std::uint32_t>(
                                   static_cast<py::ssize_t>(id.size()), id.data());
                             })
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
          "Moves the wall at this velocity (m/s) from the next step on.");
}

}  // namespace

void bind_scenes(py::module_& m) {
  bind<2>(m, "Scene2D");
  bind<3>(m, "Scene3D");
}

template class Scene<2>;
template class Scene<3>;

}  // namespace geodem::python
