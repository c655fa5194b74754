// Which code computes the contacts without extras (contacts/contact_batch.hpp), and the call
// of the batch kernel of that instruction set.
#include "contacts/contact_batch.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>

namespace geodem {

namespace {

// The widest batch path the processor runs.
ContactPath widest_path() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return ContactPath::kAvx512;
  if (__builtin_cpu_supports("avx2")) return ContactPath::kAvx2;
  return ContactPath::kBaseline;
#else
  return ContactPath::kScalar;
#endif
}

ContactPath path_from_environment() {
  const char* name = std::getenv("GEODEM_CONTACT_PATH");
  if (name != nullptr) {
    for (ContactPath p :
         {ContactPath::kScalar, ContactPath::kBaseline, ContactPath::kAvx2, ContactPath::kAvx512})
      if (std::strcmp(name, contact_path_name(p)) == 0 && contact_path_supported(p)) return p;
  }
  return default_contact_path();
}

std::atomic<int> chosen_path{-1};

}  // namespace

const char* contact_path_name(ContactPath p) {
  switch (p) {
    case ContactPath::kScalar:
      return "scalar";
    case ContactPath::kBaseline:
      return "sse2";
    case ContactPath::kAvx2:
      return "avx2";
    case ContactPath::kAvx512:
      return "avx512";
  }
  return "?";
}

bool contact_path_supported(ContactPath p) {
  static const ContactPath widest = widest_path();
  return p <= widest;
}

ContactPath default_contact_path() {
#ifdef GEODEM_SANITIZED
  // Under the sanitizers (-O1) the batches cost 1.4 times the scalar loop's time; their own
  // test (tests/validation/contact_batch_test.cpp) still runs every path there.
  return ContactPath::kScalar;
#else
  for (ContactPath p : {ContactPath::kAvx512, ContactPath::kAvx2})
    if (contact_path_supported(p)) return p;
  return ContactPath::kScalar;
#endif
}

ContactPath contact_path() {
  static const ContactPath from_environment = path_from_environment();
  const int p = chosen_path.load(std::memory_order_relaxed);
  return p < 0 ? from_environment : static_cast<ContactPath>(p);
}

bool set_contact_path(ContactPath p) {
  if (!contact_path_supported(p)) return false;
  chosen_path.store(static_cast<int>(p), std::memory_order_relaxed);
  return true;
}

template <int D, bool Periodic>
void batch_contact_forces(const BatchLaw& law, const BatchGrains& grains, double dt,
                          ContactBatch<D>& batch, int n) {
#if defined(__x86_64__) && defined(__GNUC__)
  switch (contact_path()) {
    case ContactPath::kAvx512:
      batch_kernel_avx512<D, Periodic>(law, grains, dt, batch, n);
      return;
    case ContactPath::kAvx2:
      batch_kernel_avx2<D, Periodic>(law, grains, dt, batch, n);
      return;
    default:
      batch_kernel_sse2<D, Periodic>(law, grains, dt, batch, n);
  }
#else
  (void)law, (void)grains, (void)dt, (void)batch, (void)n;  // never called: the scalar loop runs
#endif
}

template void batch_contact_forces<2, false>(const BatchLaw&, const BatchGrains&, double,
                                             ContactBatch<2>&, int);
template void batch_contact_forces<2, true>(const BatchLaw&, const BatchGrains&, double,
                                            ContactBatch<2>&, int);
template void batch_contact_forces<3, false>(const BatchLaw&, const BatchGrains&, double,
                                             ContactBatch<3>&, int);
template void batch_contact_forces<3, true>(const BatchLaw&, const BatchGrains&, double,
                                            ContactBatch<3>&, int);

}  // namespace geodem
