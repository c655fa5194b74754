#include "contacts_binding.hpp"

#include <pybind11/numpy.h>

#include <vector>

#include "measure/contact_network.hpp"

namespace geodem::python {

namespace py = pybind11;

namespace {

// Rows of D-vectors as an (n, D) array (a copy).
template <int D, class Rows>
py::array_t<double> matrix(const Rows& rows) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows.size()), py::ssize_t{D}});
  double* out = a.mutable_data();
  for (const auto& r : rows)
    for (int k = 0; k < D; ++k) *out++ = r[k];
  return a;
}

}  // namespace

template <int D>
py::dict contact_arrays(const World<D>& w) {
  const auto c = contact_network(w);
  const auto n = static_cast<py::ssize_t>(c.size());
  py::array_t<bool> b(n);
  for (py::ssize_t k = 0; k < n; ++k) b.mutable_data()[k] = c.bonded[static_cast<std::size_t>(k)];
  py::dict out;
  out["i"] = py::array_t<std::uint32_t>(n, c.i.data());
  out["j"] = py::array_t<std::uint32_t>(n, c.j.data());
  out["normal"] = matrix<D>(c.normal);
  out["overlap"] = py::array_t<double>(n, c.overlap.data());
  out["normal_force"] = py::array_t<double>(n, c.normal_force.data());
  out["tangential_force"] = matrix<D>(c.tangential_force);
  out["bonded"] = b;
  return out;
}
template <int D>
py::dict wall_contact_arrays(const World<D>& w) {
  const auto c = wall_contacts(w);
  const auto n = static_cast<py::ssize_t>(c.size());
  py::dict out;
  out["grain"] = py::array_t<std::uint32_t>(n, c.grain.data());
  out["wall"] = py::array_t<std::uint32_t>(n, c.wall.data());
  out["normal"] = matrix<D>(c.normal);
  out["overlap"] = py::array_t<double>(n, c.overlap.data());
  out["normal_force"] = py::array_t<double>(n, c.normal_force.data());
  out["tangential_force"] = matrix<D>(c.tangential_force);
  return out;
}

template py::dict contact_arrays<2>(const World<2>&);
template py::dict wall_contact_arrays<2>(const World<2>&);
template py::dict wall_contact_arrays<3>(const World<3>&);
template py::dict contact_arrays<3>(const World<3>&);

}  // namespace geodem::python
