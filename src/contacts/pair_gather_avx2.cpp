// The vector gather pass for AVX2 (contacts/pair_gather_kernel.hpp); built with that set's flags.
#include "contacts/pair_gather_kernel.hpp"

GEODEM_PAIR_GATHER(avx2, Avx2)
