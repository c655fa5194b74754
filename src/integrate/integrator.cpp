#include "integrate/integrator.hpp"

#include <algorithm>

namespace geodem {

namespace {

inline double sign(double x) { return (x > 0.0) - (x < 0.0); }

// Applies local damping to an acceleration given the half-step velocity.
inline void damp(double& a, double v_half, double alpha, double dt) {
  a *= 1.0 - alpha * sign(a * (v_half + 0.5 * dt * a));
}
template <typename V>
inline void damp(V& a, const V& v_half, double alpha, double dt) {
  for (int k = 0; k < a.size(); ++k) damp(a[k], v_half[k], alpha, dt);
}

}  // namespace

template <int D>
void integrate(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  auto& P = world.particles;
  const std::size_t n = P.size();
  const double dt = world.dt, alpha = world.local_damping;
  const Vec g = world.gravity;
  double max_d2 = world.max_disp2;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(P.flags[i] & kFixed)) {
      Vec a = P.force[i] * P.inv_mass[i] + g;
      Rot aw = P.torque[i] * P.inv_inertia[i];
      if (alpha > 0.0) {
        damp(a, P.vel[i], alpha, dt);
        damp(aw, P.angvel[i], alpha, dt);
      }
      P.vel[i] += a * dt;
      P.angvel[i] += aw * dt;
    }
    P.pos[i] += P.vel[i] * dt;
    Dim<D>::rotate(P.orient[i], P.angvel[i], dt);
    max_d2 = std::max(max_d2, (P.pos[i] - P.pos_at_build[i]).squaredNorm());
  }
  world.max_disp2 = max_d2;
}

template <int D>
void move_walls(World<D>& world) {
  for (auto& w : world.walls) {
    const auto d = w.velocity * world.dt;
    w.point += d;
    w.end += d;
    w.displacement += d;
  }
}

template void integrate<2>(World<2>&);
template void integrate<3>(World<3>&);
template void move_walls<2>(World<2>&);
template void move_walls<3>(World<3>&);

}  // namespace geodem
