// The Python module `geodem` (docs/python.md): any scenario kind run from a file or a dict, as
// `geodem run` runs it, and scenes stepped from Python with numpy views of the grains.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.hpp"
#include "io/checkpoint.hpp"
#include "io/run_output.hpp"
#include "kinds/scenario_kind.hpp"
#include "scene/scene_settings.hpp"
#include "scene_binding.hpp"

namespace py = pybind11;

namespace {

// A Python value as a TOML node: bool, int, float, str, list/tuple and dict (nested).
toml::table to_table(const py::dict& d, const std::string& where);

void insert(toml::array& a, py::handle v, const std::string& where);

template <typename Put>
void put_value(py::handle v, const std::string& where, Put&& put) {
  if (py::isinstance<py::bool_>(v)) {
    put(v.cast<bool>());
  } else if (py::isinstance<py::int_>(v)) {
    put(v.cast<long long>());
  } else if (py::isinstance<py::float_>(v)) {
    put(v.cast<double>());
  } else if (py::isinstance<py::str>(v)) {
    put(v.cast<std::string>());
  } else if (py::isinstance<py::dict>(v)) {
    put(to_table(v.cast<py::dict>(), where));
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    toml::array a;
    for (auto item : v) insert(a, item, where);
    put(std::move(a));
  } else if (py::hasattr(v, "tolist")) {  // numpy arrays and scalars
    put_value(v.attr("tolist")(), where, put);
  } else {
    throw geodem::InputError("<dict>", 0, where,
                             "expected a bool, number, string, list or dict, got " +
                                 py::str(py::type::of(v)).cast<std::string>());
  }
}

void insert(toml::array& a, py::handle v, const std::string& where) {
  put_value(v, where, [&a](auto&& x) { a.push_back(std::forward<decltype(x)>(x)); });
}

toml::table to_table(const py::dict& d, const std::string& where) {
  toml::table t;
  for (auto [k, v] : d) {
    const std::string key = py::str(k);
    const std::string path = where.empty() ? key : where + "." + key;
    put_value(v, path, [&](auto&& x) { t.insert_or_assign(key, std::forward<decltype(x)>(x)); });
  }
  return t;
}

// A scenario given as a path or a dict, with --set style overrides for a path.
geodem::LoadedScenario load(py::handle scenario, const std::vector<std::string>& overrides,
                            std::string& name) {
  if (py::isinstance<py::dict>(scenario)) {
    if (!overrides.empty())
      throw geodem::InputError("<dict>", 0, "overrides", "edit the dict instead");
    name = "<dict>";
    return geodem::load_known_scenario_table(to_table(scenario.cast<py::dict>(), ""), name);
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
        const auto l = load(scenario, overrides, name);
        if (l.kind != "scene")
          throw geodem::InputError(name, l.kind_line, "kind",
                                   "geodem.scene builds kind = \"scene\"; run the other kinds "
                                   "with geodem.run");
        geodem::SceneSettings s = geodem::read_scene(l.root, name);
        if (s.dimension == 2) return py::cast(geodem::python::Scene<2>(std::move(s)));
        return py::cast(geodem::python::Scene<3>(std::move(s)));
      },
      py::arg("scenario"), py::arg("overrides") = std::vector<std::string>{},
      "Builds the world of a scene (a path or a dict) as `geodem run` does, to step it from "
      "Python: a Scene2D or Scene3D.");
}
