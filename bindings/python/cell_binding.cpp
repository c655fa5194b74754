// The periodic cell driven from Python (docs/python.md): the engine's cell
// (world/periodic_cell.hpp) and its servo (controllers/cell_servo.hpp), stepped inside the
// engine like any other controller.
#include "cell_binding.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "controllers/cell_servo.hpp"
#include "measure/measurements.hpp"
#include "scene_binding.hpp"

namespace geodem::python {

namespace {

template <int D>
py::array_t<double> matrix(const typename Dim<D>::Tensor& t) {
  py::array_t<double> a({D, D});
  auto v = a.template mutable_unchecked<2>();
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) v(i, j) = t(i, j);
  return a;
}

template <int D>
typename Dim<D>::Tensor tensor(const py::array_t<double>& a, const char* what) {
  if (a.ndim() != 2 || a.shape(0) != D || a.shape(1) != D)
    throw py::value_error(std::string("expected a ") + std::to_string(D) + " x " +
                          std::to_string(D) + " array for " + what);
  auto v = a.template unchecked<2>();
  typename Dim<D>::Tensor t;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) t(i, j) = v(i, j);
  return t;
}

template <int D>
void drop_cell_servo(World<D>& w) {
  std::erase_if(w.controllers, [](const auto& c) {
    return dynamic_cast<const CellServo<D>*>(c.get()) != nullptr;
  });
}

template <int D>
void bind_cell(py::module_& m, const char* name) {
  using S = Scene<D>;
  using Axis = typename CellServo<D>::Axis;
  auto cls = py::reinterpret_borrow<py::class_<S>>(m.attr(name));
  cls.def(
         "set_periodic",
         [](S& s, const std::vector<double>& size) {
           auto& w = s.world();
           if (size.size() != static_cast<std::size_t>(D) ||
               std::any_of(size.begin(), size.end(), [](double x) { return !(x > 0.0); }))
             throw py::value_error("expected " + std::to_string(D) + " positive sizes (m)");
           if (!w.walls.empty() || !w.spars.empty())
             throw py::value_error(
                 "a periodic cell has no walls nor spar chains: remove them first");
           w.cell.periodic = true;
           w.cell.h.setZero();
           for (int k = 0; k < D; ++k) w.cell.h(k, k) = size[static_cast<std::size_t>(k)];
           w.cell.vel_grad.setZero();
           w.rebuild_needed = true;
         },
         py::arg("size"),
         "Makes the world a periodic cell [0, size] (no walls): grains leaving through a face "
         "come back through the opposite one, and contacts act across the faces.")
      .def_property_readonly(
          "cell", [](S& s) { return matrix<D>(s.world().cell.h); },
          "The periodic cell's edge vectors as the columns of a D x D array (m).")
      .def(
          "set_velocity_gradient",
          [](S& s, const py::array_t<double>& l) {
            auto& w = s.world();
            if (!w.cell.periodic) throw py::value_error("not a periodic cell: set_periodic first");
            w.cell.vel_grad = tensor<D>(l, "the velocity gradient");
          },
          py::arg("L"),
          "Deforms the cell at the velocity gradient L (1/s, D x D): dh/dt = L h, the grains "
          "carried by the affine field L x (their velocities are relative to it).")
      .def(
          "cell_stress", [](S& s) { return matrix<D>(cell_stress(s.world())); },
          "The cell's average stress at the last step (Pa, compression positive): the sum of "
          "branch x force over the contacts, over the cell's volume.")
      .def(
          "set_cell_servo",
          [](S& s, const std::vector<py::dict>& axes, double max_strain_rate, double gain) {
            auto& w = s.world();
            if (!w.cell.periodic) throw py::value_error("not a periodic cell: set_periodic first");
            if (axes.size() != static_cast<std::size_t>(D))
              throw py::value_error(
                  "expected one dict per axis, {'stress': Pa} or "
                  "{'strain_rate': 1/s}");
            std::array<Axis, D> a;
            for (int k = 0; k < D; ++k) {
              const py::dict& d = axes[static_cast<std::size_t>(k)];
              if (d.contains("stress") == d.contains("strain_rate"))
                throw py::value_error("axis " + std::to_string(k) +
                                      ": give either 'stress' (Pa) or 'strain_rate' (1/s)");
              a[k] = d.contains("stress") ? Axis{true, d["stress"].cast<double>(), 0.0}
                                          : Axis{false, 0.0, d["strain_rate"].cast<double>()};
            }
            if (!(max_strain_rate > 0.0) || !(gain > 0.0))
              throw py::value_error("expected max_strain_rate > 0 and gain > 0");
            drop_cell_servo(w);
            w.controllers.push_back(std::make_shared<CellServo<D>>(a, max_strain_rate, gain));
          },
          py::arg("axes"), py::arg("max_strain_rate"), py::arg("gain") = 0.1,
          "Drives each diagonal component of the cell's velocity gradient: {'stress': Pa} holds "
          "that axis's average stress at a target, {'strain_rate': 1/s} imposes a rate "
          "(extension positive). Replaces the cell servo if there was one.")
      .def(
          "remove_cell_servo", [](S& s) { drop_cell_servo(s.world()); },
          "Stops the cell servo; the velocity gradient keeps its last value.");
}

}  // namespace

void bind_cells(py::module_& m) {
  bind_cell<2>(m, "Scene2D");
  bind_cell<3>(m, "Scene3D");
}

}  // namespace geodem::python
