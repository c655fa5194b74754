// A scene stepped from Python (docs/python.md): the world of a `kind = "scene"` scenario built
// as `geodem run` builds it, then stepped by the caller, with numpy views of its arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "io/run_output.hpp"
#include "scene/scene_settings.hpp"
#include "world/world.hpp"

namespace geodem::python {

namespace py = pybind11;

template <int D>
class Scene {
 public:
  explicit Scene(SceneSettings settings);

  // Steps n times with the GIL released; the stress sums and contact counts of the last step
  // are measured.
  void step(std::uint64_t n);
  // Steps until `steps` steps or `until` seconds (whichever comes first), calling
  // callback(scene) every `every` steps; a callback that returns False stops the run.
  void run(py::object self, std::uint64_t steps, double until, std::uint64_t every,
           py::object callback);

  World<D>& world() { return world_; }
  const SceneSettings& settings() const { return settings_; }
  std::size_t wall_index(const std::string& name) const;

  // Appends a frame (grains, walls, chains and, with `contacts`, the contact network) to the
  // VTK series of `folder` (its .pvd index is rewritten); returns the index's path.
  std::string write_vtk(const std::string& folder, bool contacts);
  // A checkpoint file of the scene (its settings and its whole state, walls included).
  void save(const std::string& path) const;
  // The state of a checkpoint written by save() (or by a scene run of the command line).
  void load_state(const std::string& world_archive);

 private:
  SceneSettings settings_;
  World<D> world_;
  std::string vtk_folder_;

 public:
  // Positions by grain id at the moment set_reference() was called (empty: none).
  std::vector<typename Dim<D>::Vec> reference;
  // Random streams taken by clouds so far (the scenario's clouds share the first): each
  // cloud added from Python draws from a stream of its own.
  std::uint64_t clouds_added = 0;

 private:
  std::shared_ptr<VtkSeries<D>> vtk_;
};

// Registers the Scene2D and Scene3D classes.
void bind_scenes(py::module_& m);

}  // namespace geodem::python
