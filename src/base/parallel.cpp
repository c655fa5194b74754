#include "base/parallel.hpp"

#include <cstdlib>
#include <string>

namespace geodem {

namespace {
int threads_from(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return 0;
  try {
    std::size_t used = 0;
    const int n = std::stoi(v, &used);
    return used == std::string(v).size() && n > 0 ? n : 0;
  } catch (const std::exception&) {
    return 0;
  }
}
}  // namespace

int default_threads() {
  if (const int n = threads_from("GEODEM_THREADS")) return n;
  if (const int n = threads_from("OMP_NUM_THREADS")) return n;
  return 1;
}

bool built_with_openmp() {
#ifdef _OPENMP
  return true;
#else
  return false;
#endif
}

}  // namespace geodem
