// The move kernel for AVX2 (integrate/move_kernel_impl.hpp); built with that set's flags.
#include "integrate/move_kernel_impl.hpp"

GEODEM_MOVE_KERNELS(avx2, xsimd::avx2)
