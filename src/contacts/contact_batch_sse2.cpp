// The batch kernel for SSE2 (contacts/contact_batch_kernel.hpp); built with that set's flags.
#include "contacts/contact_batch_kernel.hpp"

GEODEM_BATCH_KERNELS(sse2, xsimd::sse2)
