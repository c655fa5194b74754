#include "base/index_max.hpp"

namespace geodem {

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
// (GCC's function multiversioning: one clone per set, the loader picks one; the loop is the
// same plain reduction in each, vectorised by the compiler with that set's integer maximum.)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
std::uint32_t
max_index(const std::uint32_t* p, std::size_t n, std::uint32_t floor) {
  std::uint32_t m = floor;
  for (std::size_t k = 0; k < n; ++k) m = p[k] > m ? p[k] : m;
  return m;
}

}  // namespace geodem
