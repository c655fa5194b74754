// Inertia of a geosynthetic sheet in a quasi-static test: its nodes are light and its
// elements stiff, so its own critical time step would be far shorter than the grains'.
// The nodes' inertial masses are raised so that the sheet does not set the time step; a
// quasi-static pull does not feel the sheet's inertia, and gravity still acts on the
// true mass (docs/lab_tests.md, "Pull-out").
#pragma once

#include <algorithm>
#include <limits>

#include "broadphase/neighbour_search.hpp"
#include "integrate/critical_timestep.hpp"

namespace geodem {

// Returns the factor applied to every node's mass. young: the soil's contact modulus
// (2D: kn = E, a grain on each face); J and element_length: the sheet's. A given factor
// (> 0) replaces the estimate: below it the sheet sets the automatic time step.
inline double scale_sheet_inertia(World<2>& w, double young, double J, double element_length,
                                  double given_factor = 0.0) {
  auto& S = w.spars;
  if (given_factor > 0.0) {
    for (std::size_t i = 0; i < S.nodes(); ++i) S.inertial_mass[i] = given_factor * S.mass[i];
    return given_factor;
  }
  // The grains' critical step as the run will have it: with their contacts, so the list
  // is built afresh (grains were just removed and the sheet laid: the old list is stale,
  // and without contacts the estimate is that of a grain's first collision, 2 to 3 times
  // longer in a packing, which made the nodes 5 to 8 times heavier than needed), and with
  // the nodes left out (an infinite inertia for now).
  if (w.domain) w.domain->before_build(w);
  build_neighbour_list(w);
  S.inertial_mass.assign(S.nodes(), std::numeric_limits<double>::infinity());
  // (a decomposed world: every rank's grains, so that every rank scales the sheet alike)
  double dt_grains = critical_timestep(w);
  if (w.domain) dt_grains = w.domain->min_over_ranks(dt_grains);
  const double dt = dt_grains / w.dt_safety;
  const double m_over_k = 0.5 * dt * dt;  // dt^2 = 2 m / k
  const double k_contact = 2.0 * young;
  double factor = 1.0;
  for (std::size_t i = 0; i < S.nodes(); ++i) {
    const double k = 2.0 * J / element_length + k_contact;
    factor = std::max(factor, 1.1 * k * m_over_k / S.mass[i]);
  }
  for (std::size_t i = 0; i < S.nodes(); ++i) S.inertial_mass[i] = factor * S.mass[i];
  return factor;
}

}  // namespace geodem
