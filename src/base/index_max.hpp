// The largest of a run of 32-bit indices: a pass over a slab's neighbour-list rows that tells
// the force stage how far the slab's pairs reach (base/slab_phases.hpp).
#pragma once

#include <cstddef>
#include <cstdint>

namespace geodem {

// The largest of p[0], ..., p[n - 1], or `floor` if larger (n = 0 gives `floor`). Compiled for
// AVX-512 and AVX2 too, picked when the program loads (an exact result on every path).
std::uint32_t max_index(const std::uint32_t* p, std::size_t n, std::uint32_t floor);

}  // namespace geodem
