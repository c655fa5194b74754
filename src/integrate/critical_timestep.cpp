#include "integrate/critical_timestep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "contacts/contact_law.hpp"

namespace geodem {

template <int D>
double critical_timestep(const World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = world.particles;
  const auto& L = world.nlist;
  const std::size_t n = P.size();
  static thread_local std::vector<double> kt_sum, kr_sum;
  kt_sum.assign(n, 0.0);
  kr_sum.assign(n, 0.0);

  auto add = [&](std::size_t i, double kn, double kt, double lever) {
    kt_sum[i] += std::max(kn, kt);
    kr_sum[i] += kt * lever * lever;
  };
  const bool have_list = L.start.size() == n + 1;
  for (std::size_t i = 0; have_list && i < n; ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::uint32_t j = L.other[k];
      const double rs = P.radius[i] + P.radius[j];
      const double dist = (P.pos[j] - P.pos[i]).norm();
      if (dist >= rs) continue;
      const PairLaw& law = world.pair_law(P.material[i], P.material[j]);
      const double delta = rs - dist;
      NormalResult nr = normal_force(law, P.radius[i], P.radius[j], 0.0, delta, 0.0);
      const double kn = law.law == LawKind::kLinear ? law.linear_kn(P.radius[i], P.radius[j])
                                                    : 1.5 * nr.fn / delta;  // dF/d(delta)
      add(i, kn, nr.kt, P.radius[i]);
      add(j, kn, nr.kt, P.radius[j]);
    }
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      const auto& w = world.walls[L.wall[k]];
      Vec q;
      if (!wall_closest(w, P.pos[i], q)) continue;
      const double gap =
          w.kind == WallKind::kPlane ? (P.pos[i] - w.point).dot(w.normal) : (q - P.pos[i]).norm();
      const double delta = P.radius[i] - gap;
      if (delta <= 0.0) continue;
      const PairLaw& law = world.wall_law(P.material[i], L.wall[k]);
      NormalResult nr =
          normal_force(law, P.radius[i], wall_partner_radius(law, P.radius[i]), 0.0, delta, 0.0);
      const double kn = law.law == LawKind::kLinear ? law.linear_kn(P.radius[i], P.radius[i])
                                                    : 1.5 * nr.fn / delta;
      add(i, kn, nr.kt, P.radius[i]);
    }
  }

  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (P.inv_mass[i] == 0.0) continue;
    const double m = 1.0 / P.inv_mass[i], inertia = 1.0 / P.inv_inertia[i];
    const auto& mat = world.materials[P.material[i]];
    const PairLaw& self = world.pair_law(P.material[i], P.material[i]);
    // A lone grain: one contact with an equal grain (linear) or the Rayleigh time (Hertz).
    double lone;
    if (self.law == LawKind::kLinear) {
      const double kn = self.linear_kn(P.radius[i], P.radius[i]);
      lone = std::sqrt(m / std::max(kn, self.linear_kt(kn)));
    } else {
      const double shear = mat.young / (2.0 * (1.0 + mat.poisson));
      lone = 0.2 * std::numbers::pi * P.radius[i] * std::sqrt(mat.density / shear) /
             (0.1631 * mat.poisson + 0.8766);
    }
    dt = std::min(dt, lone);
    if (kt_sum[i] > 0.0) dt = std::min(dt, std::sqrt(m / kt_sum[i]));
    if (kr_sum[i] > 0.0) dt = std::min(dt, std::sqrt(inertia / kr_sum[i]));
  }
  return world.dt_safety * dt;
}

template double critical_timestep<2>(const World<2>&);
template double critical_timestep<3>(const World<3>&);

}  // namespace geodem
