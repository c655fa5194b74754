// The move kernel for AVX-512 (integrate/move_kernel_impl.hpp); built with that set's flags.
#include "integrate/move_kernel_impl.hpp"

GEODEM_MOVE_KERNELS(avx512, xsimd::avx512f)
