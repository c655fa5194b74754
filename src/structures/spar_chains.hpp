// Geosynthetic sheets (2D) and cables (3D) as chains of dynamic spar elements (DSEM):
// nodes with lumped masses, joined by elements that carry tension only,
// T = J max(strain, 0) (and a push once an element is shorter than the sheet's thickness), with an
// optional bending stiffness at interior nodes (2D). Nodes are integrated with the grains in the
// same step; grains touch the elements (structures/spar_contacts.cpp). Structure of arrays, like
// the grains.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/dim.hpp"

namespace geodem {

enum SparNodeFlags : std::uint8_t {
  kNodeDriven = 1u << 0,  // not integrated: moves at its prescribed velocity (clamps, pulls)
};

constexpr std::int32_t kNoElement = -1;

template <int D>
struct SparChains {
  using Vec = typename Dim<D>::Vec;

  struct Chain {
    std::string name;
    std::uint32_t first_node = 0, node_count = 0;
    std::uint32_t first_element = 0;  // elements first_element .. + node_count - 2
    double bending = 0.0;             // N m / rad per metre width (2D): moment = k (angle - angle0)
  };

  // Nodes.
  std::vector<Vec> pos;
  std::vector<Vec> vel;      // half step, like the grains
  std::vector<Vec> force;    // contacts + elements this step (gravity added at integration)
  std::vector<double> mass;  // lumped physical mass: what gravity acts on
  std::vector<double> inertial_mass;  // what forces accelerate: the mass, or more when the
                                      // sheet's inertia is scaled up (quasi-static runs)
  std::vector<std::uint8_t> flags;
  std::vector<Vec> pos_at_build;  // for the neighbour list's expiry test
  // Elements.
  std::vector<std::uint32_t> node_a, node_b;
  std::vector<std::int32_t> prev, next;  // neighbouring element sharing node_a / node_b
  std::vector<double> rest_length;
  std::vector<double> stiffness;       // J: N/m in 2D (per metre width), N in 3D
  std::vector<double> half_thickness;  // contact radius of the element (capsule)
  std::vector<std::uint16_t> material;
  std::vector<std::uint32_t> chain_of;
  std::vector<double> rest_turn;  // 2D bending: rest angle from this element to `next`
  std::vector<double> tension;    // axial force of the current step (N/m in 2D; < 0: folded up)
  // Sum of the normal forces of the grains touching each element this step (both faces;
  // N/m in 2D): what a pull-out reads to split the tension among the sheet's parts.
  // Recomputed every step, so not part of a checkpoint.
  std::vector<double> contact_normal;
  std::vector<Chain> chains;

  std::size_t nodes() const { return pos.size(); }
  std::size_t elements() const { return node_a.size(); }
  bool empty() const { return pos.empty(); }
  bool driven(std::size_t i) const { return flags[i] & kNodeDriven; }

  // Adds a chain through `points` (at rest: the initial lengths are the rest lengths).
  // mass_per_length: kg/m (2D: the sheet's mass per area times 1 m width); each node
  // carries half of each element it joins. Returns the chain index.
  std::size_t add_chain(const std::string& name, const std::vector<Vec>& points, double J,
                        double mass_per_length, double thickness, std::uint16_t mat,
                        double bending = 0.0) {
    if (points.size() < 2) throw std::invalid_argument("a chain needs at least two nodes");
    if (bending != 0.0 && D != 2)
      throw std::invalid_argument("bending stiffness of spar chains is available in 2D only");
    Chain c;
    c.name = name;
    c.first_node = static_cast<std::uint32_t>(pos.size());
    c.node_count = static_cast<std::uint32_t>(points.size());
    c.first_element = static_cast<std::uint32_t>(node_a.size());
    c.bending = bending;
    for (const Vec& p : points) {
      pos.push_back(p);
      vel.push_back(Vec::Zero());
      force.push_back(Vec::Zero());
      mass.push_back(0.0);
      inertial_mass.push_back(0.0);
      flags.push_back(0);
      pos_at_build.push_back(p);
    }
    const std::size_t ne = points.size() - 1;
    for (std::size_t k = 0; k < ne; ++k) {
      const std::uint32_t a = c.first_node + static_cast<std::uint32_t>(k), b = a + 1;
      const double len = (pos[b] - pos[a]).norm();
      if (!(len > 0.0)) throw std::invalid_argument("chain '" + name + "': two nodes coincide");
      const auto e = static_cast<std::int32_t>(node_a.size());
      node_a.push_back(a);
      node_b.push_back(b);
      prev.push_back(k == 0 ? kNoElement : e - 1);
      next.push_back(k + 1 == ne ? kNoElement : e + 1);
      rest_length.push_back(len);
      stiffness.push_back(J);
      half_thickness.push_back(0.5 * thickness);
      material.push_back(mat);
      chain_of.push_back(static_cast<std::uint32_t>(chains.size()));
      rest_turn.push_back(0.0);
      tension.push_back(0.0);
      mass[a] += 0.5 * mass_per_length * len;
      mass[b] += 0.5 * mass_per_length * len;
    }
    for (std::uint32_t i = c.first_node; i < c.first_node + c.node_count; ++i)
      inertial_mass[i] = mass[i];
    if constexpr (D == 2) {
      for (std::size_t k = 0; k + 1 < ne; ++k) {
        const std::size_t e = c.first_element + k;
        rest_turn[e] = turn_angle(e);
      }
    }
    chains.push_back(c);
    return chains.size() - 1;
  }

  // 2D: signed angle from element e's direction to the next element's.
  double turn_angle(std::size_t e) const {
    const Vec u1 = pos[node_b[e]] - pos[node_a[e]];
    const auto f = static_cast<std::size_t>(next[e]);
    const Vec u2 = pos[node_b[f]] - pos[node_a[f]];
    return std::atan2(u1.x() * u2.y() - u1.y() * u2.x(), u1.dot(u2));
  }

  // 2D: how far the node after element e is bent from its rest turn (rad, in (-pi, pi]).
  double turn_from_rest(std::size_t e) const {
    return std::remainder(turn_angle(e) - rest_turn[e], 2.0 * std::numbers::pi);
  }

  // 2D: the bending moment there (N m/m), k (turn - rest turn).
  double bending_moment(std::size_t e) const {
    return chains[chain_of[e]].bending * turn_from_rest(e);
  }

  double length(std::size_t e) const { return (pos[node_b[e]] - pos[node_a[e]]).norm(); }
};

}  // namespace geodem
