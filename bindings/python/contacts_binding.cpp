#include "contacts_binding.hpp"

#include <pybind11/numpy.h>

#include <vector>

#include "measure/contact_network.hpp"

namespace geodem::python {

namespace py = pybind11;

template <int D>
py::dict contact_arrays(const World<D>& w) {
  const auto c = contact_network(w);
  const auto n = static_cast<py::ssize_t>(c.size());
  auto matrix = [n](const auto& rows) {
    py::array_t<double> a({n, py::ssize_t{D}});
    double* out = a.mutable_data();
    for (const auto& r : rows)
      for (int k = 0; k < D; ++k) *out++ = r[k];
    return a;
  };
  py::array_t<bool> b(n);
  for (py::ssize_t k = 0; k < n; ++k) b.mutable_data()[k] = c.bonded[static_cast<std::size_t>(k)];
  py::dict out;
  out["i"] = py::array_t<std::uint32_t>(n, c.i.data());
  out["j"] = py::array_t<std::uint32_t>(n, c.j.data());
  out["normal"] = matrix(c.normal);
  out["overlap"] = py::array_t<double>(n, c.overlap.data());
  out["normal_force"] = py::array_t<double>(n, c.normal_force.data());
  out["tangential_force"] = matrix(c.tangential_force);
  out["bonded"] = b;
  return out;
}
template py::dict contact_arrays<2>(const World<2>&);
template py::dict contact_arrays<3>(const World<3>&);

}  // namespace geodem::python
