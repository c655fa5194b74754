// Touching grain-grain contacts in batches of structure-of-arrays form, and the kernels that
// compute their forces several contacts at a time (one contact per vector lane).
//
// The pair loop (contacts/batched_pairs.cpp) gathers the touching pairs of consecutive rows
// into a batch, a kernel computes every contact's force, torques and new spring from the
// batch's arrays alone, and the loop then adds them to the grains in list order. Each lane
// runs the scalar law's operations in the scalar law's order (contacts/contact_law.hpp), with
// no fused multiply-add (-ffp-contract=off) and with IEEE division and square root, which
// every instruction set rounds alike: every path gives the same bits as the scalar loop
// (tests/unit/contact_batch_test.cpp).
//
// One Debian-built binary carries the kernel three times, written once with xsimd and built
// for the baseline x86-64 (SSE2, two lanes), for AVX2 (four) and for AVX-512 (eight); the
// step uses AVX-512 or AVX2 where the processor has them, else the scalar loop (as it does
// on other processors than x86-64).
#pragma once

#include <cstdint>

namespace geodem {

template <int D>
struct ContactBatch {
  static constexpr int kSize = 64;  // contacts
  static constexpr int kRot = D == 3 ? 3 : 1;
  // In, per contact: the grains i and j and the listed pair k, which the kernel reads the
  // grains' state and the spring by (BatchGrains).
  alignas(64) std::int64_t i[kSize];
  alignas(64) std::int64_t j[kSize];
  alignas(64) std::int64_t k[kSize];
  // In with clumps: how many contacts share the collision (their dashpots split the mass).
  alignas(64) double share[kSize];
  // In: the overlap, as a fraction of the smaller radius, beyond which the step stops.
  double overlap_limit = 0.0;
  // The branch d = x_j - x_i: out in a box; in a periodic cell an input with the image's shift,
  // as is the affine field's part L d of the relative velocity.
  alignas(64) double d[D][kSize];
  alignas(64) double vel_shift[D][kSize];
  // In a box from the vector gather pass (contacts/pair_gather.hpp), which measured each pair:
  // d and the radii of i and j, written with i, j and k, are read instead of loaded again from
  // the grains (`measured`).
  alignas(64) double radius_i[kSize];
  alignas(64) double radius_j[kSize];
  bool measured = false;
  // Out: the force on j, the torque terms ai (n x f) (taken from i) and -aj (n x f) (on j),
  // the normal force and the overlap.
  alignas(64) double f[D][kSize];
  alignas(64) double tqi[kRot][kSize];
  alignas(64) double tj[kRot][kSize];
  alignas(64) double fn[kSize];
  alignas(64) double delta[kSize];
  // Out: some contact of the batch overlaps beyond the limit.
  bool overlap_seen = false;
};

// The grains' state as the kernels read it (world/particles.hpp: arrays of D-vectors, of
// spins, of radii and inverse masses) and the list's springs, which they update in place.
struct BatchGrains {
  const double* pos;
  const double* vel;
  const double* angvel;
  const double* radius;
  const double* inv_mass;
  double* spring;
  bool shares;  // ContactBatch::share holds each contact's collision share
};

// Which code computes the grain-grain contacts without extras (bonds, rolling).
enum class ContactPath {
  kScalar,    // one contact after the other (the reference; always used with extras)
  kBaseline,  // batches, SSE2 (the baseline x86-64)
  kAvx2,      // batches, AVX2
  kAvx512,    // batches, AVX-512
};

const char* contact_path_name(ContactPath p);
// Whether this build and processor run a path (the scalar loop always).
bool contact_path_supported(ContactPath p);
// The path the step uses unless told otherwise: the widest batches the processor runs,
// AVX-512 or AVX2, else the scalar loop: the SSE2 batches were slower than the scalar loop on
// an Intel Xeon (faster per contact on an AMD EPYC since the add pass moves pairs; whole runs
// not yet timed: benchmarks/README.md, "The force stage per contact").
ContactPath default_contact_path();
// The path the step uses: the environment's GEODEM_CONTACT_PATH (scalar, sse2, avx2 or
// avx512) if set to a supported one, else the default, until set_contact_path.
ContactPath contact_path();
// Sets the path (tests and benchmarks compare them); false, and nothing changes, if the path
// is not supported.
bool set_contact_path(ContactPath p);

// A pair law's constants as the kernels read them (materials/material.hpp, PairLaw).
struct BatchLaw {
  bool hertz = false, constant_stiffness = false, per_unit_thickness = false;
  bool tangential_damping = false;
  double kn = 0.0, kt = 0.0, e1r = 0.0, e2r = 0.0, kt_over_kn = 0.0;
  double mu = 0.0, beta = 0.0, hertz_damp = 0.0, estar = 0.0, gstar = 0.0;
};

// Forces of the first n contacts of a batch under one pair law, by the path contact_path()
// names (not kScalar); the contacts' springs are updated in the list. The entries from n up
// to the next multiple of 8 are computed too and ignored (their springs are not written):
// they must index grains and pairs that exist (a batch starts zeroed).
template <int D, bool Periodic>
void batch_contact_forces(const BatchLaw& law, const BatchGrains& grains, double dt,
                          ContactBatch<D>& batch, int n);

// The kernel of each instruction set (contacts/contact_batch_kernel.hpp), for the dispatch.
template <int D, bool Periodic>
void batch_kernel_sse2(const BatchLaw& law, const BatchGrains& grains, double dt,
                       ContactBatch<D>& batch, int n);
template <int D, bool Periodic>
void batch_kernel_avx2(const BatchLaw& law, const BatchGrains& grains, double dt,
                       ContactBatch<D>& batch, int n);
template <int D, bool Periodic>
void batch_kernel_avx512(const BatchLaw& law, const BatchGrains& grains, double dt,
                         ContactBatch<D>& batch, int n);

}  // namespace geodem
