// Building messages and names from parts. Through a stream rather than operator+:
// GCC 12 warns falsely (-Wrestrict) on chains of std::string additions at -O3.
#pragma once

#include <sstream>
#include <string>

namespace geodem {

template <typename... T>
std::string cat(const T&... parts) {
  std::ostringstream s;
  s.precision(17);
  (s << ... << parts);
  return s.str();
}

}  // namespace geodem
