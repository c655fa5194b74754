// Spar chains (geosynthetic sheets) against closed forms:
// - a chain stretched between two nodes carries T = J strain in every element (0.1 %),
//   and nothing at all when compressed (tension only);
// - a chain hanging between two supports takes the catenary's sag and tensions
//   (S = 2 c sinh(a/c), sag = c (cosh(a/c) - 1), H = w c, T_support = w c cosh(a/c));
// - a grain resting on an element loads its two nodes with the weights (1 - t) and t:
//   their sum is the grain's weight and their moment the weight's;
// - a grain that cannot roll stays on an element tilted below the interface friction
//   angle and slides above it with a = g (sin(theta) - tan(delta) cos(theta));
// - a grain sliding along a chain keeps its friction force mu N, without a jump, as it
//   crosses from one element to the next; at a node it is counted once;
// - bending forces are minus the gradient of k_b (phi - phi0)^2 / 2 (central differences),
//   with no net force or moment;
// - a sheet flat at rest, held bent on a circular arc, is in pure bending: the moment
//   k_b x (turn per node) is the same at every arc node and no force acts on the arc's
//   inner nodes; the couple that bends it acts where the arc meets the straight parts;
// - an element pressed end to end stops folding up at the sheet's thickness: its free node
//   comes back elastically (the spring J / L0 of a linear oscillator: deepest push
//   v sqrt(m / k), speed restored), and a stiff bent sheet's end element never turns inside
//   out.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "structures/spar_dynamics.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

constexpr double kG = 9.81;

template <typename T>
class SparChain : public ::testing::Test {};
TYPED_TEST_SUITE(SparChain, Dims, DimNames);

template <int D>
std::vector<Vec<D>> straight_points(const Vec<D>& a, const Vec<D>& b, int elements) {
  std::vector<Vec<D>> p;
  for (int k = 0; k <= elements; ++k) p.push_back(a + (b - a) * (double(k) / elements));
  return p;
}

TYPED_TEST(SparChain, StretchedChainCarriesJTimesStrainAndNoCompression) {
  constexpr int D = TypeParam::value;
  World<D> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const double J = 2e5, L0 = 1.0;
  w.spars.add_chain("sheet", straight_points<D>(Vec<D>::Zero(), vec<D>(L0, 0.0), 10), J, 0.2, 0.002,
                    mat);
  auto& S = w.spars;
  const std::size_t last = S.nodes() - 1;
  S.flags[0] = S.flags[last] = kNodeDriven;
  w.auto_dt = true;
  w.local_damping = 0.3;
  // Pull the end to 1 % strain, hold, let the chain come to rest.
  const double strain = 0.01, v = 0.02;
  S.vel[last] = vec<D>(v, 0.0);
  while (S.pos[last].x() < L0 * (1.0 + strain) - 0.5 * v * w.dt) step(w);
  S.vel[last] = Vec<D>::Zero();
  const double actual = S.pos[last].x() / L0 - 1.0;
  for (int k = 0; k < 20000; ++k) step(w);
  double worst = 0.0;
  for (std::size_t e = 0; e < S.elements(); ++e)
    worst = std::max(worst, rel_err(S.tension[e], J * actual));
  report("stretched chain: max |T - J strain| / (J strain)", worst);
  EXPECT_LT(worst, 1e-3);

  // Compression: push the end back to 2 % shorter than at rest; nothing is carried.
  S.vel[last] = vec<D>(-v, 0.0);
  while (S.pos[last].x() > L0 * (1.0 - 0.02)) {
    step(w);
    for (std::size_t e = 0; e < S.elements(); ++e) ASSERT_GE(S.tension[e], 0.0);
  }
  S.vel[last] = Vec<D>::Zero();
  for (int k = 0; k < 2000; ++k) step(w);
  double tmax = 0.0, fmax = 0.0;
  for (std::size_t e = 0; e < S.elements(); ++e) tmax = std::max(tmax, S.tension[e]);
  for (std::size_t i = 0; i < S.nodes(); ++i) fmax = std::max(fmax, S.force[i].norm());
  report("compressed chain: largest tension (N/m)", tmax);
  EXPECT_EQ(tmax, 0.0);
  EXPECT_EQ(fmax, 0.0);
}

// A 2D chain of length S hanging between supports 2a apart at the same height.
TEST(SparChain2D, HangingChainTakesTheCatenary) {
  World<2> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const double a = 0.5, S_len = 1.2, mu = 1.0, J = 1e6;
  const int n = 60;  // even: a node at the middle
  // Start as a V of the right length; it settles into the catenary.
  const double h = std::sqrt(0.25 * S_len * S_len - a * a);
  std::vector<Vec<2>> pts;
  for (int k = 0; k <= n; ++k) {
    const double s = double(k) / n;
    pts.push_back(s <= 0.5 ? Vec<2>(2.0 * a * s, -2.0 * h * s)
                           : Vec<2>(2.0 * a * s, -2.0 * h * (1.0 - s)));
  }
  w.spars.add_chain("cable", pts, J, mu, 0.001, mat);
  auto& S = w.spars;
  S.flags[0] = S.flags[n] = kNodeDriven;
  w.gravity = Vec<2>(0.0, -kG);
  w.auto_dt = true;
  w.local_damping = 0.3;
  double min_tension = 0.0;
  while (w.time < 10.0) {
    step(w);
    for (double t : S.tension) min_tension = std::min(min_tension, t);
  }
  // Catenary parameter from S = 2 c sinh(a / c), by bisection.
  double lo = 0.05, hi = 10.0;
  for (int it = 0; it < 200; ++it) {
    const double c = 0.5 * (lo + hi);
    (2.0 * c * std::sinh(a / c) > S_len ? lo : hi) = c;
  }
  const double c = 0.5 * (lo + hi), wl = mu * kG;
  const double sag = c * (std::cosh(a / c) - 1.0);
  const double sag_dem = -S.pos[n / 2].y();
  const double t_mid = 0.5 * (S.tension[n / 2 - 1] + S.tension[n / 2]);
  // The first element's tension is that of the catenary at its middle: T = w c cosh(x/c).
  const double x_mid = 0.5 * (S.pos[0].x() + S.pos[1].x()) - a;
  const double t_end = S.tension[0], t_end_want = wl * c * std::cosh(x_mid / c);
  report("catenary: sag error", rel_err(sag_dem, sag));
  report("catenary: horizontal tension error", rel_err(t_mid, wl * c));
  report("catenary: first element tension error", rel_err(t_end, t_end_want));
  EXPECT_LT(rel_err(sag_dem, sag), 5e-3);
  EXPECT_LT(rel_err(t_mid, wl * c), 5e-3);
  EXPECT_LT(rel_err(t_end, t_end_want), 5e-3);
  EXPECT_GE(min_tension, 0.0);
  // Symmetric about the middle.
  report("catenary: asymmetry of the quarter points (m)",
         std::abs(S.pos[n / 4].y() - S.pos[3 * n / 4].y()));
  EXPECT_NEAR(S.pos[n / 4].y(), S.pos[3 * n / 4].y(), 1e-3 * sag);
}

// One element (0,0)-(L,0), both nodes held; grain material and sheet material with
// interface friction tan(delta).
struct GrainOnSheet {
  World<2> w;
  std::size_t grain = 0;
  double weight = 0.0;
  static constexpr double kR = 0.02, kDelta = 30.0;

  GrainOnSheet(const std::vector<Vec<2>>& nodes, double x0, bool roll) {
    const auto soil = add_material(w, linear_material(2e5, 1e5, 0.5, 1.0));
    const auto sheet = add_material(w, linear_material(2e5, 1e5, 0.5, 1.0, 1000.0, "sheet"));
    w.resolve_pair_laws();
    const double mu = std::tan(kDelta * std::numbers::pi / 180.0);
    for (auto* law : {&w.pair_laws[soil * 2 + sheet], &w.pair_laws[sheet * 2 + soil]}) law->mu = mu;
    w.spars.add_chain("sheet", nodes, 1e6, 0.5, 0.0, sheet);
    for (std::size_t i = 0; i < w.spars.nodes(); ++i) w.spars.flags[i] = kNodeDriven;
    grain = w.particles.add(Vec<2>(x0, kR), kR, 2600.0, soil);
    if (!roll) w.particles.inv_inertia[grain] = 0.0;  // rotation blocked: it can only slide
    weight = kG / w.particles.inv_mass[grain];
    w.gravity = Vec<2>(0.0, -kG);
    w.auto_dt = true;
    w.dt_safety = 0.1;  // many steps per contact period: the tests follow the motion closely
  }
  // Settles with damping under vertical gravity.
  void settle() {
    w.local_damping = 0.7;
    for (int k = 0; k < 20000; ++k) step(w);
    w.local_damping = 0.0;
  }
  Vec<2> node_force_sum() const {
    Vec<2> f = Vec<2>::Zero();
    for (const auto& x : w.spars.force) f += x;
    return f;
  }
};

TEST(SparChain2D, GrainLoadsTheNodesWithLinearWeights) {
  const double L = 0.1, t = 0.3;
  GrainOnSheet g({Vec<2>(0.0, 0.0), Vec<2>(L, 0.0)}, t * L, true);
  g.settle();
  const auto& S = g.w.spars;
  const double fa = -S.force[0].y(), fb = -S.force[1].y();
  report("grain on element: node force sum error", rel_err(fa + fb, g.weight));
  report("grain on element: node b share error", rel_err(fb, t * g.weight));
  EXPECT_LT(rel_err(fa + fb, g.weight), 1e-6);
  // Moment about node a: F_b L = W x_grain.
  const double x = g.w.particles.pos[g.grain].x();
  EXPECT_LT(rel_err(fb * L, g.weight * x), 1e-6);
  EXPECT_LT(rel_err(fa * L, g.weight * (L - x)), 1e-6);
  EXPECT_NEAR(S.force[0].x() + S.force[1].x(), 0.0, 1e-9 * g.weight);
}

// Settles, then tilts gravity slowly (with damping) up to theta_static, then at once to
// theta without damping; returns the grain's acceleration along the element (least-
// squares slope of its velocity over `seconds`). A slow tilt keeps the tangential spring
// from overshooting its static value (a sudden one would double it and slip early).
double tilted_acceleration(GrainOnSheet& g, double theta_static, double theta, double seconds) {
  g.settle();
  g.w.local_damping = 0.7;
  const double ramp = 0.5, t_ramp = g.w.time;
  while (g.w.time < t_ramp + 2.0 * ramp) {
    const double th = theta_static * std::min((g.w.time - t_ramp) / ramp, 1.0);
    g.w.gravity = kG * Vec<2>(std::sin(th), -std::cos(th));
    step(g.w);
  }
  g.w.local_damping = 0.0;
  g.w.gravity = kG * Vec<2>(std::sin(theta), -std::cos(theta));
  std::vector<double> ts, vs;
  const double t0 = g.w.time;
  while (g.w.time < t0 + seconds) {
    step(g.w);
    ts.push_back(g.w.time);
    vs.push_back(g.w.particles.vel[g.grain].x());
  }
  double st = 0, sv = 0, stt = 0, stv = 0;
  const double m = static_cast<double>(ts.size());
  for (std::size_t k = 0; k < ts.size(); ++k)
    st += ts[k], sv += vs[k], stt += ts[k] * ts[k], stv += ts[k] * vs[k];
  return (m * stv - st * sv) / (m * stt - st * st);
}

TEST(SparChain2D, GrainSlidesAtTheInterfaceFrictionAngle) {
  const double delta = GrainOnSheet::kDelta * std::numbers::pi / 180.0;
  const std::vector<Vec<2>> nodes = {Vec<2>(-1.0, 0.0), Vec<2>(1.0, 0.0)};
  {
    GrainOnSheet g(nodes, 0.0, false);
    const double theta = std::atan(0.98 * std::tan(delta));
    const double a = tilted_acceleration(g, theta, theta, 0.5);
    // At rest on its tangential spring: displaced by at most the spring's stretch.
    const double stretch = g.weight * std::sin(theta) / 1e5;
    report("tan(theta) = 0.98 tan(delta): acceleration (m/s2)", a);
    EXPECT_LT(std::abs(a), 1e-3);
    EXPECT_LT(std::abs(g.w.particles.pos[g.grain].x()), 1.5 * stretch);
  }
  {
    GrainOnSheet g(nodes, 0.0, false);
    const double theta = std::atan(1.02 * std::tan(delta));
    const double a = tilted_acceleration(g, std::atan(0.98 * std::tan(delta)), theta, 0.5);
    const double want = kG * (std::sin(theta) - std::tan(delta) * std::cos(theta));
    report("tan(theta) = 1.02 tan(delta): acceleration error", rel_err(a, want));
    EXPECT_LT(rel_err(a, want), 0.01);
  }
}

TEST(SparChain2D, SlidingGrainKeepsItsForceAcrossElements) {
  const double delta = GrainOnSheet::kDelta * std::numbers::pi / 180.0;
  // Three elements: the grain, just short of the first shared node, slides slowly across
  // two nodes (tilted just past tan(delta)). Slowly, so that a spring lost at a node would
  // show: a fresh spring grows by kt v dt a step, far below mu N at these speeds.
  GrainOnSheet g({Vec<2>(0.0, 0.0), Vec<2>(0.03, 0.0), Vec<2>(0.06, 0.0), Vec<2>(0.2, 0.0)}, 0.028,
                 false);
  g.settle();
  g.w.local_damping = 0.7;
  const double theta_static = std::atan(0.98 * std::tan(delta)), ramp = 0.5;
  const double t0 = g.w.time;
  while (g.w.time < t0 + 2.0 * ramp) {
    const double th = theta_static * std::min((g.w.time - t0) / ramp, 1.0);
    g.w.gravity = kG * Vec<2>(std::sin(th), -std::cos(th));
    step(g.w);
  }
  g.w.local_damping = 0.0;
  const double theta = std::atan(1.01 * std::tan(delta));
  g.w.gravity = kG * Vec<2>(std::sin(theta), -std::cos(theta));
  const auto& P = g.w.particles;
  auto ratio = [&] {
    const Vec<2> f = P.force[g.grain];  // contact force on the grain
    return -f.x() / f.y();
  };
  // Wait until the spring reaches Coulomb's limit (sliding), then follow the ratio of
  // tangential to normal force across both nodes.
  while (std::abs(ratio() - std::tan(delta)) > 1e-9 * std::tan(delta)) step(g.w);
  double worst = 0.0, worst_sum = 0.0, v_cross = 0.0;
  int steps = 0;
  while (P.pos[g.grain].x() < 0.065) {
    step(g.w);
    ++steps;
    if (std::abs(P.pos[g.grain].x() - 0.06) < 1e-3) v_cross = P.vel[g.grain].x();
    worst = std::max(worst, std::abs(ratio() - std::tan(delta)) / std::tan(delta));
    const Vec<2> f = P.force[g.grain];
    worst_sum = std::max(worst_sum, (g.node_force_sum() + f).norm() / f.norm());
  }
  // The growth of a fresh spring in one step at the crossing speed, against mu N.
  const double fresh = 1e5 * v_cross * g.w.dt / (std::tan(delta) * g.weight * std::cos(theta));
  report("sliding across nodes: max |Ft/Fn - tan(delta)| / tan(delta)", worst);
  report("sliding across nodes: fresh spring / Coulomb limit at the crossing", fresh);
  EXPECT_GT(steps, 100);
  EXPECT_LT(fresh, 0.25);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_sum, 1e-12);
}

TEST(SparChain2D, GrainOnASharedNodeIsCountedOnce) {
  // A flat chain with the grain right above a shared node, and a shallow convex bend.
  for (const double bend_deg : {0.0, 10.0}) {
    const double b = bend_deg * std::numbers::pi / 180.0;
    GrainOnSheet g({Vec<2>(-0.1 * std::cos(b), -0.1 * std::sin(b)), Vec<2>(0.0, 0.0),
                    Vec<2>(0.1 * std::cos(b), -0.1 * std::sin(b))},
                   0.0, false);
    g.settle();
    const Vec<2> sum = g.node_force_sum();
    report("grain on a node (bend " + std::to_string(int(bend_deg)) + " deg): load error",
           rel_err(-sum.y(), g.weight));
    EXPECT_LT(rel_err(-sum.y(), g.weight), 1e-6);
    EXPECT_LT(std::abs(sum.x()), 1e-6 * g.weight);
  }
}

TYPED_TEST(SparChain, FoldedElementKeepsItsNodesTheThicknessApart) {
  constexpr int D = TypeParam::value;
  EXPECT_EQ(axial_force(2e5, 1.01, 1.0, 0.1), 2e5 * (1.01 - 1.0));         // stretched: J strain
  EXPECT_EQ(axial_force(2e5, 0.5, 1.0, 0.1), 0.0);                         // slack: nothing
  EXPECT_NEAR(axial_force(2e5, 0.08, 2.0, 0.1), -2e5 * 0.02 / 2.0, 1e-9);  // folded up: a push
  World<D> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const double J = 1e4, L0 = 0.1, mu = 2.0, thickness = 0.01, v = 0.05;
  w.spars.add_chain("sheet", {Vec<D>::Zero(), vec<D>(L0, 0.0)}, J, mu, thickness, mat);
  auto& S = w.spars;
  S.flags[0] = kNodeDriven;
  S.vel[1] = vec<D>(-v, 0.0);  // the free node runs at the held one
  const double m = 0.5 * mu * L0, k = J / L0;
  w.dt = 0.01 * std::sqrt(m / k);  // fine enough for the oscillator's closed form
  double closest = L0;
  while (S.vel[1].x() < 0.0 || S.pos[1].x() < thickness) {
    step(w);
    closest = std::min(closest, S.pos[1].x());
    ASSERT_GT(S.pos[1].x(), 0.0);
  }
  // The push acts on the node's mass (half the element's) with stiffness J / L0.
  const double expected = thickness - v * std::sqrt(m / k);
  report("folded element: deepest approach (m)", closest);
  report("folded element: deepest approach expected (m)", expected);
  EXPECT_NEAR(closest, expected, 0.01 * (thickness - expected));
  EXPECT_NEAR(S.vel[1].x(), v, 1e-3 * v);
}

TEST(SparChain2D, StiffSheetsEndElementDoesNotTurnInsideOut) {
  World<2> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  // Three elements, the first two held; the free end is thrown back at its neighbour,
  // end to end, as a grain dragging a sheet's end can do. Without the push at the thickness
  // the element shrinks to nothing, flips, and its bending moment (k_b pi) then acts over a
  // vanishing length.
  const double kb = 50.0, L0 = 0.024, thickness = 0.0024, v = 0.5;
  w.spars.add_chain("sheet",
                    {Vec<2>(0.0, 0.0), Vec<2>(L0, 0.0), Vec<2>(2 * L0, 0.0), Vec<2>(3 * L0, 0.0)},
                    1e6, 6.0, thickness, mat, kb);
  auto& S = w.spars;
  S.flags[0] = S.flags[1] = S.flags[2] = kNodeDriven;
  S.vel[3] = Vec<2>(-v, 0.0);
  w.dt = 0.01 * std::sqrt(S.inertial_mass[3] / (1e6 / L0));  // resolves the push's oscillation
  double closest = L0, worst_turn = 0.0;
  // Until the end node has come back out beyond the thickness (before the element pulls).
  for (int k = 0; k < 1000000 && (S.vel[3].x() < 0.0 || S.pos[3].x() - S.pos[2].x() < thickness);
       ++k) {
    step(w);
    closest = std::min(closest, S.pos[3].x() - S.pos[2].x());
    worst_turn = std::max(worst_turn, std::abs(S.turn_angle(1)));
  }
  report("stiff sheet's end: closest approach (m)", closest);
  report("stiff sheet's end: largest turn (rad)", worst_turn);
  EXPECT_GT(closest, 0.5 * thickness);
  EXPECT_LT(worst_turn, 1e-9);
  EXPECT_TRUE(S.pos[3].allFinite());
  EXPECT_NEAR(S.vel[3].x(), v, 1e-3 * v);  // thrown back at its speed
}

TEST(SparChain2D, BendingForcesDeriveFromTheirPotential) {
  World<2> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const double kb = 3.0;
  // A bent chain at rest (its rest turns), then deformed; J = 0 isolates the bending.
  w.spars.add_chain("sheet",
                    {Vec<2>(0.0, 0.0), Vec<2>(0.1, 0.02), Vec<2>(0.2, 0.0), Vec<2>(0.27, -0.05)},
                    0.0, 0.1, 0.0, mat, kb);
  auto& S = w.spars;
  S.pos[1] += Vec<2>(0.004, 0.013);
  S.pos[2] += Vec<2>(-0.006, 0.004);
  auto energy = [&]() {
    double e = 0.0;
    for (std::size_t k = 0; k + 1 < S.elements(); ++k) {
      const double d = S.turn_angle(k) - S.rest_turn[k];
      e += 0.5 * kb * d * d;
    }
    return e;
  };
  for (auto& f : S.force) f.setZero();
  spar_element_forces(w);
  const std::vector<Vec<2>> force = S.force;
  double worst = 0.0, scale = 0.0;
  Vec<2> net = Vec<2>::Zero();
  double moment = 0.0;
  for (std::size_t i = 0; i < S.nodes(); ++i) {
    net += force[i];
    moment += S.pos[i].x() * force[i].y() - S.pos[i].y() * force[i].x();
    scale = std::max(scale, force[i].norm());
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-7, x0 = S.pos[i][k];
      S.pos[i][k] = x0 + h;
      const double ep = energy();
      S.pos[i][k] = x0 - h;
      const double em = energy();
      S.pos[i][k] = x0;
      worst = std::max(worst, std::abs(force[i][k] + (ep - em) / (2.0 * h)));
    }
  }
  report("bending: max |F + dE/dx| / max |F|", worst / scale);
  EXPECT_GT(scale, 1.0);
  EXPECT_LT(worst / scale, 1e-6);
  EXPECT_LT(net.norm(), 1e-12 * scale);
  EXPECT_LT(std::abs(moment), 1e-12 * scale);
}

TEST(SparChain2D, FlatSheetOnAnArcIsInPureBending) {
  World<2> w;
  const auto mat = add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  const double kb = 50.0, R = 0.1, step_angle = 0.1;
  // Two straight elements, 12 arc pieces of radius R (a quarter turn and a bit), two more.
  std::vector<Vec<2>> p = {Vec<2>(-2 * R * step_angle, R), Vec<2>(-R * step_angle, R)};
  const int pieces = 12;
  for (int j = 0; j <= pieces; ++j)
    p.emplace_back(R * std::sin(j * step_angle), R * std::cos(j * step_angle));
  const Vec<2> end = p.back(),
               tangent(std::cos(pieces * step_angle), -std::sin(pieces * step_angle));
  p.push_back(end + R * step_angle * tangent);
  p.push_back(end + 2 * R * step_angle * tangent);
  w.spars.add_chain("sheet", p, 0.0, 0.1, 0.0, mat, kb);  // J = 0: bending alone
  auto& S = w.spars;
  std::fill(S.rest_turn.begin(), S.rest_turn.end(), 0.0);  // flat at rest
  for (auto& f : S.force) f.setZero();
  spar_element_forces(w);
  // Chords of equal arc pieces turn by step_angle at the arc's inner nodes and by half of
  // it where the arc meets a tangent straight part.
  const std::size_t first_arc = 2, last_arc = first_arc + pieces;
  double largest = 0.0;
  for (const auto& f : S.force) largest = std::max(largest, f.norm());
  for (std::size_t i = first_arc + 1; i < last_arc; ++i)
    EXPECT_NEAR(S.bending_moment(i - 1), -kb * step_angle, 1e-9 * kb);
  for (std::size_t i = first_arc + 2; i + 1 < last_arc; ++i)
    EXPECT_LT(S.force[i].norm(), 1e-9 * largest) << "arc node " << i;
  // The bending couple is k_b step_angle over an element's length, at the arc's ends.
  report("flat sheet on an arc: largest node force (N/m)", largest);
  EXPECT_GT(largest, 0.5 * kb * step_angle / (R * step_angle));
  EXPECT_LT(largest, 3.0 * kb * step_angle / (R * step_angle));
}

}  // namespace
}  // namespace geodem::test
