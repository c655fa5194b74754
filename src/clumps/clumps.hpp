// Rigid clumps: bodies whose members are grains of Particles (so that the contact
// stage, the neighbour search and the outputs see members as ordinary discs/spheres).
// A member carries its clump index and its offset in the clump's body frame; each step
// the members' forces are summed onto the clump, the clump is integrated as one rigid
// body (clumps/clump_dynamics.cpp) and the members are placed back on it.
// Members of one clump never touch each other (the neighbour search skips such pairs).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "base/dim.hpp"
#include "clumps/clump_template.hpp"

namespace geodem {

inline constexpr std::uint32_t kNoClump = 0xffffffffu;

template <int D>
struct Clumps {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  using Orient = typename Dim<D>::Orient;

  std::vector<Vec> pos;     // centre of mass
  std::vector<Vec> vel;     // at the half step, as for grains
  std::vector<Rot> angvel;  // world frame, at the half step
  // 3D: angular momentum in the world frame (half step), the integrated quantity; the
  // angular velocity follows from it and the orientation. Unused in 2D.
  std::vector<Rot> angmom;
  std::vector<Orient> orient;  // body frame (principal axes) to world
  // The same as a matrix, kept up to date by the integration: placing members then
  // costs a matrix product, not trigonometry (2D) or quaternion algebra (3D).
  std::vector<Eigen::Matrix<double, D, D>> rotation;
  std::vector<Vec> force;
  std::vector<Rot> torque;
  std::vector<double> inv_mass;
  std::vector<Rot> inertia;      // principal moments (2D: the polar moment)
  std::vector<Rot> inv_inertia;  // their inverses
  std::vector<double> volume;    // of the union of the members (overlaps once)
  // Stable identifier (creation order): clumps are renumbered with their members.
  std::vector<std::uint32_t> id;
  std::uint32_t next_id = 0;  // unique even after clumps were removed
  // Held in place (not integrated) while non-zero; empty when no clump is held.
  std::vector<std::uint8_t> held;
  // In a decomposed world (domain/slab_domain.hpp) the last `ghosts` clumps are copies of
  // clumps another rank owns, there to name the body their ghost members belong to: they are
  // neither integrated nor measured here. Zero on one process.
  std::size_t ghosts = 0;

  std::size_t size() const { return pos.size(); }
  // The clumps this process integrates and measures: [0, owned()).
  std::size_t owned() const { return pos.size() - ghosts; }

  // Body-to-world rotation matrix of an orientation.
  static Eigen::Matrix<double, D, D> matrix(const Orient& q) {
    if constexpr (D == 2) {
      const double c = std::cos(q), s = std::sin(q);
      return (Eigen::Matrix2d() << c, -s, s, c).finished();
    } else {
      return q.toRotationMatrix();
    }
  }
  static double min_moment(const Rot& i) {
    if constexpr (D == 2) {
      return i;
    } else {
      return i.minCoeff();
    }
  }

  // Reorders every array: new index k holds the clump that had index order[k] (a
  // shorter order keeps only those it lists).
  void permute(const std::vector<std::uint32_t>& order) {
    auto apply = [&](auto& v) {
      if (v.empty()) return;
      std::remove_reference_t<decltype(v)> out(order.size());
      for (std::size_t k = 0; k < order.size(); ++k) out[k] = v[order[k]];
      v.swap(out);
    };
    apply(pos), apply(vel), apply(angvel), apply(angmom), apply(orient), apply(rotation);
    apply(force), apply(torque), apply(inv_mass), apply(inertia), apply(inv_inertia);
    apply(volume), apply(id), apply(held);
  }

  // Homothetic scaling by m about each centre of mass (radius-growth compaction);
  // the members' offsets and radii are scaled by the caller with the other grains.
  void scale(double m) {
    const double mass_factor = std::pow(m, D), inertia_factor = std::pow(m, D + 2);
    for (std::size_t c = 0; c < size(); ++c) {
      inv_mass[c] /= mass_factor;
      inertia[c] *= inertia_factor;
      inv_inertia[c] /= inertia_factor;
      volume[c] *= mass_factor;
      if constexpr (D == 3) angmom[c] *= inertia_factor;  // keeps the angular velocity
    }
  }
};

template <int D>
struct World;

// Adds a clump of template `t` scaled by `scale`, centre of mass at `x`, orientation
// `q` (body to world), of the given density and material. Returns the clump index.
template <int D>
std::size_t add_clump(World<D>& world, const ResolvedClump<D>& t, const typename Dim<D>::Vec& x,
                      const typename Dim<D>::Orient& q, double scale, double density,
                      std::uint16_t material, const typename Dim<D>::Vec& v = Dim<D>::Vec::Zero());

// Random orientation, uniform over rotations (2D: an angle in [0, 2 pi)).
template <int D>
typename Dim<D>::Orient random_orientation(double u1, double u2, double u3);
template <>
Dim<2>::Orient random_orientation<2>(double u1, double u2, double u3);
template <>
Dim<3>::Orient random_orientation<3>(double u1, double u2, double u3);

}  // namespace geodem
