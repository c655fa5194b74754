#include "contacts_binding.hpp"

#include <pybind11/numpy.h>

#include <vector>

#include "contacts/contact_law.hpp"

namespace geodem::python {

namespace py = pybind11;

template <int D>
py::dict contact_arrays(const World<D>& w) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = w.particles;
  const auto& L = w.nlist;
  const bool extras = !L.extra.empty();
  std::vector<std::uint32_t> ii, jj;
  std::vector<double> normal, overlap, fn, ft;
  std::vector<bool> bonded;
  for (std::size_t i = 0; i + 1 < L.start.size(); ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::uint32_t j = L.other[k];
      const Vec d = P.pos[j] - P.pos[i];
      const double dist = d.norm(), rs = P.radius[i] + P.radius[j];
      const bool bond = extras && L.extra[k].bonded;
      if ((dist >= rs && !bond) || dist <= 0.0) continue;
      const Vec n = d / dist;
      const double delta = rs - dist;
      const PairLaw& law = w.pair_law(P.material[i], P.material[j]);
      ii.push_back(static_cast<std::uint32_t>(i));
      jj.push_back(j);
      overlap.push_back(delta);
      fn.push_back(bond || delta <= 0.0
                       ? law.linear_kn(P.radius[i], P.radius[j]) * delta
                       : normal_force(law, P.radius[i], P.radius[j], 0.0, delta, 0.0).fn);
      const Vec t = tangential_force<D>(L.spring[k], n);
      for (int a = 0; a < D; ++a) normal.push_back(n[a]), ft.push_back(t[a]);
      bonded.push_back(bond);
    }
  }
  const auto n = static_cast<py::ssize_t>(ii.size());
  auto matrix = [n](const std::vector<double>& v) {
    py::array_t<double> a({n, py::ssize_t{D}});
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
  };
  py::array_t<bool> b(n);
  for (py::ssize_t k = 0; k < n; ++k) b.mutable_data()[k] = bonded[static_cast<std::size_t>(k)];
  py::dict out;
  out["i"] = py::array_t<std::uint32_t>(n, ii.data());
  out["j"] = py::array_t<std::uint32_t>(n, jj.data());
  out["normal"] = matrix(normal);
  out["overlap"] = py::array_t<double>(n, overlap.data());
  out["normal_force"] = py::array_t<double>(n, fn.data());
  out["tangential_force"] = matrix(ft);
  out["bonded"] = b;
  return out;
}

template py::dict contact_arrays<2>(const World<2>&);
template py::dict contact_arrays<3>(const World<3>&);

}  // namespace geodem::python
