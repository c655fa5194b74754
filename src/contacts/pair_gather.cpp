// The call of the vector gather pass of an instruction set (contacts/pair_gather.hpp).
#include "contacts/pair_gather.hpp"

namespace geodem {

bool pair_gather_has(ContactPath p) {
#if defined(__x86_64__) && defined(__GNUC__)
  return p == ContactPath::kAvx2 || p == ContactPath::kAvx512;
#else
  (void)p;
  return false;
#endif
}

template <int D>
int gather_touching(ContactPath p, const PairGatherInput& in, PairWindow& w, ContactBatch<D>& batch,
                    int n) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (p == ContactPath::kAvx512) return gather_touching_avx512<D>(in, w, batch, n);
  return gather_touching_avx2<D>(in, w, batch, n);
#else
  (void)p, (void)in, (void)w, (void)batch;  // never called: pair_gather_has is false
  return n;
#endif
}

template int gather_touching<2>(ContactPath, const PairGatherInput&, PairWindow&, ContactBatch<2>&,
                                int);
template int gather_touching<3>(ContactPath, const PairGatherInput&, PairWindow&, ContactBatch<3>&,
                                int);

}  // namespace geodem
