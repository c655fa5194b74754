// The move of free grains (velocity and position, Cundall's local damping) several grains at a
// time, for the integrator's common case: no periodic cell and no orientations to track
// (integrate/integrator.cpp keeps the scalar loop for those, for clumps' own move and for the
// grains left over after the last whole block).
//
// A grain's D position components lie side by side in memory, so eight grains' components form
// whole vectors; the kernel computes the scalar loop's operations in the same order on each
// component (a = F / m + g, a -= alpha |a| sign(v + a dt / 2), v += a dt, x += v dt; the same
// for the spin), with no fused multiply-add and selects instead of the scalar loop's tests of
// each grain's flags: every instruction set gives the scalar loop's bits
// (tests/unit/move_kernel_test.cpp).
//
// Built once per instruction set, like the contact kernel (contacts/contact_batch.hpp): AVX2 and
// AVX-512, each file with that set's flags; the step runs the one of contact_path().
#pragma once

#include <cstddef>
#include <cstdint>

namespace geodem {

// The grains' arrays as flat doubles (D per position, velocity and force; R = 3 in 3D, 1 in 2D
// per spin and torque) and the step's constants.
struct MoveArrays {
  double* pos;
  double* vel;
  double* angvel;
  const double* force;
  const double* torque;
  const double* inv_mass;
  const double* inv_inertia;
  const std::uint8_t* flags;
};

struct MoveConstants {
  double dt = 0.0;
  double alpha = 0.0;  // local damping; 0: none
  double gravity[3] = {0.0, 0.0, 0.0};
  std::uint8_t left_alone = 0;  // flags of grains not moved here (clump members, ghosts)
  std::uint8_t fixed = 0;       // flags of grains that keep their velocity
};

// Grains handled per block: the kernels take [first, last) with last - first a multiple of it.
inline constexpr std::size_t kMoveBlock = 8;

// Moves grains first to last - 1; returns the largest speed squared among those moved (0 if
// none), as the scalar loop computes it.
template <int D>
double move_kernel_avx2(const MoveConstants& c, const MoveArrays& a, std::size_t first,
                        std::size_t last);
template <int D>
double move_kernel_avx512(const MoveConstants& c, const MoveArrays& a, std::size_t first,
                          std::size_t last);

}  // namespace geodem
