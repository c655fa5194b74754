// The batch kernel for AVX2 (contacts/contact_batch_kernel.hpp); built with that set's flags.
#include "contacts/contact_batch_kernel.hpp"

GEODEM_BATCH_KERNELS(avx2, xsimd::avx2)
