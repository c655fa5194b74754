// Pieces of the layered gravity deposit that the 2D lab kinds over a deposited soil share
// (pull-out, interface shear): the material indices, the soil's friction while it is
// deposited, the sheet's interface law, the grains' area statistics that size each layer,
// and the drop of one layer as a loose random cloud above the surface.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "base/error.hpp"
#include "base/exact_sum.hpp"
#include "base/random.hpp"
#include "clumps/grain_mix.hpp"
#include "lab/deposit_settings.hpp"
#include "measure/measurements.hpp"
#include "world/world.hpp"

namespace geodem {

// Material indices of these kinds' worlds: soil, smooth walls, sheet.
enum : std::uint16_t { kDepositSoil = 0, kDepositWalls = 1, kDepositSheet = 2 };

// The materials of these kinds' worlds, in the order above: the sheet's is the soil's with the
// local interface friction `interface_deg`, without rolling resistance or cohesion.
inline std::vector<Material> deposit_materials(const Material& soil, const Material& walls,
                                               double interface_deg) {
  Material sheet = soil;
  sheet.name = "sheet";
  sheet.friction = std::tan(interface_deg * (std::numbers::pi / 180.0));
  sheet.rolling_friction = sheet.twisting_friction = 0.0;
  sheet.normal_cohesion = sheet.shear_cohesion = 0.0;
  return {soil, walls, sheet};
}

// Sets the soil's contact friction; its rolling friction follows in proportion (none
// while the friction is 0).
inline void set_soil_friction(World<2>& w, const Material& soil, double mu) {
  PairLaw& law = w.pair_laws[kDepositSoil * 3 + kDepositSoil];
  const double ratio = soil.friction > 0.0 ? mu / soil.friction : 0.0;
  law.mu = mu;
  law.roll_mu = soil.rolling_friction * ratio;
  law.twist_mu = soil.twisting_friction * ratio;
}

// Soil against sheet: the interface friction alone (no rolling resistance, no bond).
inline void set_interface_laws(World<2>& w, double tan_delta) {
  for (auto* law : {&w.pair_laws[kDepositSoil * 3 + kDepositSheet],
                    &w.pair_laws[kDepositSheet * 3 + kDepositSoil]}) {
    law->mu = tan_delta;
    law->roll_mu = law->twist_mu = 0.0;
    law->bond_tension = law->bond_shear = 0.0;
  }
  w.update_contact_extras();
}

// The laws and settings of a deposit's world, its walls and sheet added: the pair laws
// resolved, the interface law, the deposit friction; gravity, the automatic time step,
// renumbering every 10 steps, the threads and the deposit's damping.
inline void configure_deposit_world(World<2>& w, const DepositedSoil& s, double interface_deg,
                                    double dt_safety, int dt_update_interval, int threads) {
  constexpr double kDegree = std::numbers::pi / 180.0;
  w.resolve_pair_laws();
  set_interface_laws(w, std::tan(interface_deg * kDegree));
  if (s.deposit_friction_deg >= 0.0)
    set_soil_friction(w, s.soil, std::tan(s.deposit_friction_deg * kDegree));
  w.gravity = Dim<2>::Vec(0.0, -9.81);
  w.auto_dt = true;
  w.dt_safety = dt_safety;
  w.dt_update_interval = dt_update_interval;
  w.sort_interval = 10;
  w.threads = threads;
  w.local_damping = s.deposit_damping;
}

// The largest of every rank's `here` in a decomposed world (a rank's ghosts are copies of
// grains another owns: a largest value may count them too).
inline double largest_over_ranks(const World<2>& w, double here) {
  return w.domain ? -w.domain->min_over_ranks(-here) : here;
}

inline double top_of_grains(const World<2>& w) {
  double t = 0.0;
  for (std::size_t i = 0; i < w.particles.size(); ++i)
    t = std::max(t, w.particles.pos[i].y() + w.particles.radius[i]);
  return largest_over_ranks(w, t);
}

// The highest point of the grains and of the spar chains' elements (a sheet laid on the
// soil): a layer's cloud starts there, clear of both. The chains are whole on every rank.
inline double top_of_solids(const World<2>& w) {
  double t = top_of_grains(w);
  const auto& S = w.spars;
  for (std::size_t e = 0; e < S.elements(); ++e)
    t = std::max({t, S.pos[S.node_a[e]].y() + S.half_thickness[e],
                  S.pos[S.node_b[e]].y() + S.half_thickness[e]});
  return t;
}

// Median over 12 columns of [x0, x1] of the highest grain top: the free surface's level
// (a grain bouncing above it does not raise it).
inline double surface_level(const World<2>& w, double x0, double x1) {
  constexpr int kCols = 12;
  std::vector<double> col_top(kCols, 0.0);
  for (std::size_t i = 0; i < w.particles.size(); ++i) {
    const double x = w.particles.pos[i].x();
    if (x < x0 || x > x1) continue;
    const auto c = static_cast<std::size_t>(
        std::clamp(static_cast<int>((x - x0) / (x1 - x0) * kCols), 0, kCols - 1));
    col_top[c] = std::max(col_top[c], w.particles.pos[i].y() + w.particles.radius[i]);
  }
  for (double& t : col_top) t = largest_over_ranks(w, t);
  std::nth_element(col_top.begin(), col_top.begin() + kCols / 2, col_top.end());
  return col_top[kCols / 2];
}

// A soil still falling or flowing: kinetic energy above a tenth of the energy of every
// grain dropping by its own radius, sum(rho pi r^2 g r) (a soil at rest holds 1e-4 of it or
// less). The unbalanced force ratio alone can be small in a falling cloud whose few
// contacts are hard collisions: a layer once counted as settled while still in the air.
inline bool soil_moving(const World<2>& w, double density) {
  const auto& P = w.particles;
  double e = 0.0;
  if (!w.domain) {
    for (double r : P.radius) e += density * 3.14159265358979323846 * r * r * r;
  } else {  // (every rank's own grains, summed exactly: the same for any number of ranks)
    std::vector<ExactSum> sum(1);
    for (std::size_t i = 0; i < P.size(); ++i)
      if (!(P.flags[i] & kGhost))
        sum[0].add(density * 3.14159265358979323846 * P.radius[i] * P.radius[i] * P.radius[i]);
    w.domain->sum(sum);
    e = sum[0].value();
  }
  return kinetic_energy(w) > 0.1 * e * w.gravity.norm();
}

// Layer sizes: a dense 2D packing's porosity guess, and the fraction of its height the
// bounding discs of a loose cloud fill (random sequential addition jams near 0.5 in 2D).
constexpr double kDensePorosity = 0.16, kLooseFill = 0.3;

// The mean area of a grain and the area of the grains' bounding discs over their own.
struct GrainAreas {
  double mean = 0.0, bound_ratio = 1.0;
};
inline GrainAreas grain_areas(const std::vector<ResolvedKind<2>>& kinds, double radius,
                              double fuzz) {
  double fsum = 0.0, bound_area = 0.0;
  GrainAreas a;
  for (const auto& k : kinds) fsum += k.fraction;
  for (const auto& k : kinds) {
    const double scale2 = k.size * k.size * (1.0 + fuzz * fuzz / 3.0) * radius * radius;
    a.mean += k.fraction / fsum * k.clump.volume * scale2;
    bound_area += k.fraction / fsum * Dim<2>::volume(k.clump.bounding_radius) * scale2;
  }
  a.bound_ratio = bound_area / a.mean;
  return a;
}

// Drops the grains of a layer `dense` thick once settled over [x0, x1], as a loose random
// cloud from height `base` up. A cloud that cannot be placed is an input error.
inline void drop_layer(World<2>& w, const DepositedSoil& s, const std::string& file,
                       const std::vector<ResolvedKind<2>>& kinds, const GrainAreas& areas,
                       Random& rng, double x0, double x1, double base, double dense) {
  using Vec = Dim<2>::Vec;
  const auto count =
      static_cast<std::size_t>(std::ceil((1.0 - kDensePorosity) * (x1 - x0) * dense / areas.mean));
  double loose = dense * (1.0 - kDensePorosity) * areas.bound_ratio / kLooseFill;
  // A thin last layer (a few grains into a gap narrower than a clump) may find no room at
  // its loose height: the cloud is dropped from higher up, twice as high each try (a
  // failed try places nothing, so a layer that fits at once is as before).
  for (int attempt = 0;; ++attempt) {
    try {
      add_random_grains<2>(w, kinds, Vec(x0, base), Vec(x1, base + loose), count, 1.0 - kLooseFill,
                           s.radius_fuzz, s.soil.density, kDepositSoil, rng, Vec::Zero(), s.radius);
      break;
    } catch (const std::runtime_error& e) {
      if (attempt == 3) throw InputError(file, 0, "soil.layer_thickness", e.what());
      loose *= 2.0;
    }
  }
  w.rebuild_needed = true;
}

}  // namespace geodem
