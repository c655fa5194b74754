// Mass properties of clumps (clumps/clump_template.cpp) against closed-form values:
// two equal touching discs/spheres (no overlap: sums of the members with the parallel
// axis theorem) and overlapping equal pairs (the union counted once). For the
// overlapping pairs the slice integrands are closed-form functions of the position
// along the axis; they are integrated here by Gauss quadrature after the substitution
// u = r sin(t), which is exact to rounding for these smooth integrands.
// Stated accuracy of the column integration: 1e-6 (2D), 2e-5 (3D) relative.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "clumps/clump_template.hpp"
#include "test_util.hpp"

namespace geodem::test {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTol2 = 1e-6, kTol3 = 2e-5;

// Integral of f over [a, b] (|a|, |b| <= r) after u = r sin(t): 64 Gauss points in 8 panels.
template <typename F>
double integrate_u(F&& f, double a, double b, double r) {
  static const double x[4] = {0.3399810435848563, 0.8611363115940526, -0.3399810435848563,
                              -0.8611363115940526};
  static const double wq[4] = {0.6521451548625461, 0.3478548451374538, 0.6521451548625461,
                               0.3478548451374538};
  const double ta = std::asin(a / r), tb = std::asin(b / r);
  const int panels = 64;
  const double h = (tb - ta) / panels;
  double sum = 0.0;
  for (int p = 0; p < panels; ++p) {
    const double mid = ta + (p + 0.5) * h;
    for (int g = 0; g < 4; ++g) {
      const double t = mid + 0.5 * h * x[g];
      sum += 0.5 * h * wq[g] * f(r * std::sin(t)) * r * std::cos(t);
    }
  }
  return sum;
}

TEST(ClumpMass, TwoTouchingDiscs) {
  const double r = 0.7;
  const auto p = union_mass_properties<2>({Vec<2>(0, 0), Vec<2>(2 * r, 0)}, {r, r});
  const double a1 = kPi * r * r;
  report("2D touching pair area", rel_err(p.volume, 2 * a1));
  EXPECT_LT(rel_err(p.volume, 2 * a1), kTol2);
  EXPECT_NEAR(p.centroid.x(), r, 1e-9 * r);
  EXPECT_NEAR(p.centroid.y(), 0.0, 1e-9 * r);
  const double polar = 2 * (0.5 * a1 * r * r + a1 * r * r);  // 3 pi r^4
  report("2D touching pair polar moment", rel_err(p.inertia.trace(), polar));
  EXPECT_LT(rel_err(p.inertia.trace(), polar), kTol2);
}

TEST(ClumpMass, TwoTouchingSpheres) {
  const double r = 0.3;
  const auto p = union_mass_properties<3>({Vec<3>(0, 0, 0), Vec<3>(0, 2 * r, 0)}, {r, r});
  const double v1 = 4.0 / 3.0 * kPi * r * r * r;
  EXPECT_LT(rel_err(p.volume, 2 * v1), kTol3);
  EXPECT_NEAR(p.centroid.y(), r, 1e-9 * r);
  const double axial = 2 * 0.4 * v1 * r * r, transverse = 2 * (0.4 * v1 * r * r + v1 * r * r);
  report("3D touching pair axial moment", rel_err(p.inertia(1, 1), axial));
  report("3D touching pair transverse moment", rel_err(p.inertia(0, 0), transverse));
  EXPECT_LT(rel_err(p.inertia(1, 1), axial), kTol3);
  EXPECT_LT(rel_err(p.inertia(0, 0), transverse), kTol3);
  EXPECT_LT(rel_err(p.inertia(2, 2), transverse), kTol3);
  EXPECT_LT(std::abs(p.inertia(0, 1)) / transverse, kTol3);
}

// Equal members at +-d/2 on the x axis; u = x - d/2 runs over [-d/2, r] for the right
// half (the union is symmetric), where the slice belongs to the right member.
TEST(ClumpMass, OverlappingDiscs) {
  const double r = 1.0, d = 1.2;
  const auto p = union_mass_properties<2>({Vec<2>(-d / 2, 0), Vec<2>(d / 2, 0)}, {r, r});
  auto h = [r](double u) { return std::sqrt(std::max(r * r - u * u, 0.0)); };
  const double area = 2 * integrate_u([&](double u) { return 2 * h(u); }, -d / 2, r, r);
  // Closed form: two discs minus the lens.
  const double lens = 2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d);
  ASSERT_LT(rel_err(area, 2 * kPi * r * r - lens), 1e-12);
  const double polar = 2 * integrate_u(
                               [&](double u) {
                                 const double x = u + d / 2, hu = h(u);
                                 return x * x * 2 * hu + 2 * hu * hu * hu / 3;
                               },
                               -d / 2, r, r);
  report("2D overlapping pair area", rel_err(p.volume, area));
  report("2D overlapping pair polar moment", rel_err(p.inertia.trace(), polar));
  EXPECT_LT(rel_err(p.volume, area), kTol2);
  EXPECT_LT(p.centroid.norm(), 1e-9);
  EXPECT_LT(rel_err(p.inertia.trace(), polar), kTol2);
}

TEST(ClumpMass, OverlappingSpheres) {
  const double r = 1.0, d = 0.8;
  const auto p = union_mass_properties<3>({Vec<3>(-d / 2, 0, 0), Vec<3>(d / 2, 0, 0)}, {r, r});
  // Slices are discs of radius^2 a2 = r^2 - u^2: polynomials in u, exact closed forms.
  auto prim_v = [r](double u) { return r * r * u - u * u * u / 3; };
  const double volume = 2 * kPi * (prim_v(r) - prim_v(-d / 2));
  const double lens = kPi * (4 * r + d) * (2 * r - d) * (2 * r - d) / 12;
  ASSERT_LT(rel_err(volume, 2 * 4.0 / 3.0 * kPi - lens), 1e-12);
  auto prim_axial = [r](double u) {
    return std::pow(r, 4) * u - 2 * r * r * u * u * u / 3 + std::pow(u, 5) / 5;
  };
  const double axial = kPi * (prim_axial(r) - prim_axial(-d / 2));  // 2 x int pi a^4/2
  const double transverse = 2 * kPi *
                            integrate_u(
                                [&](double u) {
                                  const double a2 = r * r - u * u, x = u + d / 2;
                                  return a2 * a2 / 4 + x * x * a2;
                                },
                                -d / 2, r, r);
  report("3D overlapping pair volume", rel_err(p.volume, volume));
  report("3D overlapping pair axial moment", rel_err(p.inertia(0, 0), axial));
  report("3D overlapping pair transverse moment", rel_err(p.inertia(1, 1), transverse));
  EXPECT_LT(rel_err(p.volume, volume), kTol3);
  EXPECT_LT(p.centroid.norm(), kTol3 * r);
  EXPECT_LT(rel_err(p.inertia(0, 0), axial), kTol3);
  EXPECT_LT(rel_err(p.inertia(1, 1), transverse), kTol3);
  EXPECT_LT(rel_err(p.inertia(2, 2), transverse), kTol3);
}

// An asymmetric clump: the resolved members sit in the principal frame, where the
// inertia tensor recomputed from them is diagonal with the principal moments (to the
// integration accuracy: the columns of the rotated shape fall elsewhere).
TEST(ClumpMass, PrincipalFrame) {
  ClumpTemplate<3> t;
  t.centre = {Vec<3>(0.1, 0.2, -0.3), Vec<3>(1.0, 0.4, 0.2), Vec<3>(0.3, 1.1, 0.5)};
  t.radius = {0.5, 0.4, 0.3};
  const auto c = resolve_clump(t);
  const auto p = union_mass_properties<3>(c.offset, c.radius);
  EXPECT_LT(p.centroid.norm(), kTol3);
  const double scale = p.inertia.diagonal().maxCoeff();
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(rel_err(p.inertia(a, a), c.principal[a]), kTol3);
    for (int b = 0; b < 3; ++b)
      if (a != b) {
        EXPECT_LT(std::abs(p.inertia(a, b)) / scale, kTol3);
      }
  }
  EXPECT_TRUE(c.principal[0] < c.principal[1] && c.principal[1] < c.principal[2]);
  // Distances between members are those of the template (a rigid motion).
  EXPECT_NEAR((c.offset[0] - c.offset[1]).norm(), (t.centre[0] - t.centre[1]).norm(), 1e-12);
  EXPECT_NEAR((c.offset[1] - c.offset[2]).norm(), (t.centre[1] - t.centre[2]).norm(), 1e-12);
}

TEST(ClumpMass, BuiltinTemplates) {
  ClumpTemplate<2> t;
  ASSERT_TRUE(builtin_clump_template<2>("pair_0.9", t));
  EXPECT_DOUBLE_EQ(t.radius[1] / t.radius[0], 0.9);
  const auto c = resolve_clump(t);
  EXPECT_FALSE(builtin_clump_template<2>("no_such_grain", t));
  EXPECT_LT(rel_err(c.volume, kPi * (1.0 + 0.81)), kTol2);  // touching: no overlap
}

}  // namespace
}  // namespace geodem::test
