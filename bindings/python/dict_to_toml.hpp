// Python values as TOML, so that a dict carries a scenario's keys (or a part of one: a wall,
// a cloud, a chain) through the same readers, with the same checks, as a TOML file.
#pragma once

#include <pybind11/pybind11.h>

#include <toml++/toml.h>
#include <string>

namespace geodem::python {

// A dict as a TOML table: bool, int, float, str, list/tuple (numpy arrays too) and dict
// (nested) values; `where` prefixes the keys named in errors.
toml::table to_table(const pybind11::dict& d, const std::string& where);

}  // namespace geodem::python
