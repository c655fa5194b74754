#include "dict_to_toml.hpp"

#include "base/error.hpp"

namespace geodem::python {

namespace py = pybind11;

namespace {

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
    throw InputError("<dict>", 0, where,
                     "expected a bool, number, string, list or dict, got " +
                         py::str(py::type::of(v)).cast<std::string>());
  }
}

void insert(toml::array& a, py::handle v, const std::string& where) {
  put_value(v, where, [&a](auto&& x) { a.push_back(std::forward<decltype(x)>(x)); });
}

}  // namespace

toml::table to_table(const py::dict& d, const std::string& where) {
  toml::table t;
  for (auto [k, v] : d) {
    const std::string key = py::str(k);
    const std::string path = where.empty() ? key : where + "." + key;
    put_value(v, path, [&](auto&& x) { t.insert_or_assign(key, std::forward<decltype(x)>(x)); });
  }
  return t;
}

}  // namespace geodem::python
