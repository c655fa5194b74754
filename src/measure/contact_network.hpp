// The contact network: every grain-grain contact touching (or bonded) at the last step, with
// its normal, overlap and forces; and the fabric tensor of its normals. What force-chain
// pictures (io/vtk_writer.hpp), the Python module's contact arrays and the fabric columns
// of a scene's history are made of.
#pragma once

#include <cstdint>
#include <vector>

#include "world/world.hpp"

namespace geodem {

template <int D>
struct ContactNetwork {
  using Vec = typename Dim<D>::Vec;
  std::vector<std::uint32_t> i, j;  // grain indices, i < j
  std::vector<Vec> normal;          // unit, from i to j
  std::vector<double> overlap;      // m (negative: a bond stretched open)
  // The law's elastic normal force (N; N/m in 2D), negative for a bond in tension; the
  // dashpot's share is left out (it depends on the step's velocities, not on the state).
  std::vector<double> normal_force;
  std::vector<Vec> tangential_force;  // on j
  std::vector<std::uint8_t> bonded;
  std::size_t size() const { return i.size(); }
};

template <int D>
ContactNetwork<D> contact_network(const World<D>& world);

// The grain-wall contacts touching at the last step: grain index, wall index, the normal
// from the grain to the wall, overlap, the law's elastic normal force (on the wall) and the
// tangential force on the wall. The walls' resultants (Wall::force) add the dashpots.
template <int D>
struct WallContacts {
  using Vec = typename Dim<D>::Vec;
  std::vector<std::uint32_t> grain, wall;
  std::vector<Vec> normal;
  std::vector<double> overlap, normal_force;
  std::vector<Vec> tangential_force;
  std::size_t size() const { return grain.size(); }
};

template <int D>
WallContacts<D> wall_contacts(const World<D>& world);

// Fabric tensor F = <n (x) n> over the grain-grain contacts touching (trace 1; I/D when
// isotropic); zero without contacts.
template <int D>
typename Dim<D>::Tensor fabric_tensor(const World<D>& world);

// Its anisotropy: D (largest eigenvalue - smallest), 0 when isotropic. For a 2D fabric
// 1/2 (1 + a cos 2(theta - theta0)) it is the usual a.
template <int D>
double fabric_anisotropy(const typename Dim<D>::Tensor& fabric);

}  // namespace geodem
