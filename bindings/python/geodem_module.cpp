// The Python module `geodem` (docs/python.md): any scenario kind run from a file or a dict, as
// `geodem run` runs it, and scenes stepped from Python with numpy views of the grains.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.hpp"
#include "builder_binding.hpp"
#include "cell_binding.hpp"
#include "dict_to_toml.hpp"
#include "io/checkpoint.hpp"
#include "io/run_output.hpp"
#include "kinds/scenario_kind.hpp"
#include "scene/scene_settings.hpp"
#include "scene_binding.hpp"
#include "servo_binding.hpp"

namespace py = pybind11;

namespace {

// A scenario given as a path or a dict, with --set style overrides for a path.
geodem::LoadedScenario load(py::handle scenario, const std::vector<std::string>& overrides,
                            std::string& name) {
  if (py::isinstance<py::dict>(scenario)) {
    if (!overrides.empty())
      throw geodem::InputError("<dict>", 0, "overrides", "edit the dict instead");
    name = "<dict>";
    return geodem::load_known_scenario_table(
        geodem::python::to_table(scenario.cast<py::dict>(), ""), name);
  }
  name = py::str(scenario).cast<std::string>();  // str or os.PathLike
  return geodem::load_known_scenario(name, overrides);
}

py::object read_summary(const std::string& dir) {
  std::ifstream in(dir + "/summary.json");
  std::stringstream text;
  text << in.rdbuf();
  return py::module_::import("json").attr("loads")(text.str());
}

}  // namespace

PYBIND11_MODULE(geodem, m) {
  m.doc() = "geodem: discrete element method for geotechnical engineering (docs/python.md)";
  m.attr("__version__") = geodem::version();
  static py::exception<geodem::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<geodem::InstabilityError> unstable(m, "InstabilityError",
                                                          PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const geodem::InputError& e) {
      input_error(e.what());
    } catch (const geodem::InstabilityError& e) {
      unstable(e.what());
    }
  });

  m.def(
      "check",
      [](py::handle scenario, const std::vector<std::string>& overrides, int threads) {
        std::string name;
        const auto l = load(scenario, overrides, name);
        return geodem::find_kind(l, name).check(l.root, name, threads, true);
      },
      py::arg("scenario"), py::arg("overrides") = std::vector<std::string>{},
      py::arg("threads") = 1,
      "Checks a scenario (a path or a dict) as `geodem check` does; returns what it is, raises "
      "geodem.InputError naming the key and what was expected.");

  m.def(
      "run",
      [](py::handle scenario, const std::string& out, const std::vector<std::string>& overrides,
         int threads, bool overwrite, bool resume, bool quiet) {
        std::string name;
        const auto l = load(scenario, overrides, name);
        const geodem::ScenarioKind& kind = geodem::find_kind(l, name);
        (void)kind.check(l.root, name, threads, false);  // the memory estimate
        geodem::RunOptions opt;
        opt.out_dir = out;
        opt.quiet = quiet;
        opt.threads = threads;
        opt.resume = resume;
        if (resume && !kind.resumable)
          throw geodem::InputError(name, l.kind_line, "kind",
                                   "kind \"" + l.kind + "\" writes no checkpoints");
        geodem::KindRun done;
        {
          py::gil_scoped_release release;
          done = kind.run(l, name, opt, overwrite);
        }
        py::object summary = read_summary(out);
        summary["exit_code"] = done.exit_code;
        return summary;
      },
      py::arg("scenario"), py::arg("out"), py::arg("overrides") = std::vector<std::string>{},
      py::arg("threads") = 1, py::arg("overwrite") = false, py::arg("resume") = false,
      py::arg("quiet") = true,
      "Runs a scenario of any kind (a path or a dict) into the folder `out`, writing the same "
      "files as `geodem run`; returns summary.json as a dict (plus its exit_code).");

  geodem::python::bind_scenes(m);
  geodem::python::bind_builders(m);
  geodem::python::bind_servos(m);
  geodem::python::bind_cells(m);
  m.def(
      "load",
      [](const std::string& path) -> py::object {
        geodem::Checkpoint c;
        try {
          c = geodem::read_checkpoint(path);
        } catch (const geodem::CheckpointError& e) {
          throw geodem::InputError(path, 0, "path",
                                   std::string("not a readable checkpoint: ") + e.what());
        }
        if (c.kind != "scene")
          throw geodem::InputError(path, 0, "kind",
                                   "a checkpoint of kind \"" + c.kind +
                                       "\": geodem.load reads those of scenes (resume the other "
                                       "kinds with geodem.run(..., resume=True))");
        std::string name;
        const auto l = load(py::module_::import("json").attr("loads")(c.scenario), {}, name);
        geodem::SceneSettings s = geodem::read_scene(l.root, path);
        if (s.dimension == 2) {
          geodem::python::Scene<2> scene(std::move(s));
          scene.load_state(c.world);
          return py::cast(std::move(scene));
        }
        geodem::python::Scene<3> scene(std::move(s));
        scene.load_state(c.world);
        return py::cast(std::move(scene));
      },
      py::arg("path"),
      "A scene from a checkpoint file written by Scene.save (or by a scene run of the command "
      "line): the same state, bit for bit, stepped on as if it had never stopped.");
  m.def(
      "scene",
      [](py::handle scenario, const std::vector<std::string>& overrides) -> py::object {
        std::string name;
        py::object given = py::reinterpret_borrow<py::object>(scenario);
        if (py::isinstance<py::dict>(scenario) && !scenario.contains("kind")) {
          py::dict d(scenario.cast<py::dict>());  // a copy: the caller's dict stays as it is
          d["kind"] = "scene";
          given = d;
        }
        const auto l = load(given, overrides, name);
        if (l.kind != "scene")
          throw geodem::InputError(name, l.kind_line, "kind",
                                   "geodem.scene builds kind = \"scene\"; run the other kinds "
                                   "with geodem.run");
        // Grains may come later, from Python (add_grains, add_cloud, add_clumps), and Python
        // says how long it runs.
        geodem::SceneSettings s = geodem::read_scene(l.root, name, true);
        if (s.dimension == 2) return py::cast(geodem::python::Scene<2>(std::move(s)));
        return py::cast(geodem::python::Scene<3>(std::move(s)));
      },
      py::arg("scenario"), py::arg("overrides") = std::vector<std::string>{},
      "Builds the world of a scene (a path or a dict; a dict's kind defaults to \"scene\") as "
      "`geodem run` does, to step it from Python: a Scene2D or Scene3D. It may have no grains "
      "yet: add them with add_grains, add_cloud or add_clumps.");
}
