// Solid area and volume of grains cut by a box, against closed forms:
// disc_rectangle_area (exact in 2D) and solid_volume_in_box (2D exact, 3D by quadrature).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "test_util.hpp"

namespace geodem::test {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kBig = 1e3;  // a rectangle side far beyond the disc

// Area of the circular segment beyond a chord at distance d from the centre (|d| <= r).
double segment_area(double r, double d) {
  return r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
}

// Volume of the spherical cap of height h (0 <= h <= 2r).
double cap_volume(double r, double h) {
  return kPi * h * h * (3.0 * r - h) / 3.0;
}

TEST(DiscRectangleArea, WholeDiscInside) {
  EXPECT_NEAR(disc_rectangle_area(0.3, -0.2, 0.5, -1.0, -1.0, 1.0, 1.0), kPi * 0.25, 1e-14);
  // Touching the rectangle's sides from inside.
  EXPECT_NEAR(disc_rectangle_area(0.0, 0.0, 1.0, -1.0, -1.0, 1.0, 1.0), kPi, 1e-14);
}

TEST(DiscRectangleArea, Disjoint) {
  EXPECT_EQ(disc_rectangle_area(0.0, 0.0, 1.0, 2.0, -1.0, 3.0, 1.0), 0.0);
  EXPECT_EQ(disc_rectangle_area(0.0, 0.0, 1.0, -1.0, 1.0, 1.0, 2.0), 0.0);
  EXPECT_EQ(disc_rectangle_area(0.0, 0.0, 1.0, 1.0, 1.0, -1.0, 2.0), 0.0);  // empty box
}

TEST(DiscRectangleArea, HalfDiscs) {
  const double cx = 1.5, cy = -0.7, r = 0.4, half = 0.5 * kPi * r * r;
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, cx, -kBig, kBig, kBig), half, 1e-14);
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, -kBig, -kBig, cx, kBig), half, 1e-14);
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, -kBig, cy, kBig, kBig), half, 1e-14);
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, -kBig, -kBig, kBig, cy), half, 1e-14);
}

TEST(DiscRectangleArea, QuarterDiscAtEachCorner) {
  const double cx = -2.0, cy = 3.0, r = 1.3, quarter = 0.25 * kPi * r * r;
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, cx, cy, kBig, kBig), quarter, 1e-13);
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, -kBig, cy, cx, kBig), quarter, 1e-13);
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, -kBig, -kBig, cx, cy), quarter, 1e-13);
  EXPECT_NEAR(disc_rectangle_area(cx, cy, r, cx, -kBig, kBig, cy), quarter, 1e-13);
}

TEST(DiscRectangleArea, SegmentsBeyondAChord) {
  const double r = 2.0;
  for (double d : {-1.9, -1.0, -0.3, 0.0, 0.5, 1.2, 1.99}) {
    SCOPED_TRACE(d);
    const double want = segment_area(r, d);
    EXPECT_NEAR(disc_rectangle_area(0.0, 0.0, r, d, -kBig, kBig, kBig), want, 1e-12 * r * r);
    EXPECT_NEAR(disc_rectangle_area(0.0, 0.0, r, -kBig, d, kBig, kBig), want, 1e-12 * r * r);
    EXPECT_NEAR(disc_rectangle_area(0.0, 0.0, r, -kBig, -kBig, -d, kBig), want, 1e-12 * r * r);
    EXPECT_NEAR(disc_rectangle_area(0.0, 0.0, r, -kBig, -kBig, kBig, -d), want, 1e-12 * r * r);
  }
}

// A centred square of half side s, r/sqrt(2) < s < r: the disc less four segments.
TEST(DiscRectangleArea, CentredSquareCuttingFourSegments) {
  const double r = 1.0;
  for (double s : {0.75, 0.9, 0.99}) {
    const double want = kPi * r * r - 4.0 * segment_area(r, s);
    EXPECT_NEAR(disc_rectangle_area(0.0, 0.0, r, -s, -s, s, s), want, 1e-13);
  }
  // Inside the disc entirely (s <= r/sqrt(2)): the square itself.
  EXPECT_NEAR(disc_rectangle_area(0.0, 0.0, r, -0.7, -0.7, 0.7, 0.7), 1.96, 1e-13);
}

// Cutting a disc into four rectangles at random lines gives back the whole disc.
TEST(DiscRectangleArea, AdditiveOverRandomPartitions) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int t = 0; t < 200; ++t) {
    const double a = u(rng), b = u(rng), r = 1.0;
    const double sum = disc_rectangle_area(0, 0, r, -kBig, -kBig, a, b) +
                       disc_rectangle_area(0, 0, r, a, -kBig, kBig, b) +
                       disc_rectangle_area(0, 0, r, -kBig, b, a, kBig) +
                       disc_rectangle_area(0, 0, r, a, b, kBig, kBig);
    EXPECT_NEAR(sum, kPi, 1e-13);
  }
}

template <int D>
double volume_of_one(const Vec<D>& c, double r, const Box<D>& box) {
  World<D> w;
  w.particles.add(c, r, 1000.0, 0);
  return solid_volume_in_box(w, box);
}

TEST(SolidVolumeInBox, DiscCutsIn2D) {
  const double r = 0.5, area = kPi * r * r;
  const Box<2> box{vec<2>(0.0, 0.0), vec<2>(2.0, 3.0)};
  EXPECT_NEAR(volume_of_one<2>(vec<2>(1.0, 1.0), r, box), area, 1e-14);
  EXPECT_NEAR(volume_of_one<2>(vec<2>(0.0, 1.0), r, box), 0.5 * area, 1e-14);
  EXPECT_NEAR(volume_of_one<2>(vec<2>(2.0, 3.0), r, box), 0.25 * area, 1e-14);
  EXPECT_NEAR(volume_of_one<2>(vec<2>(1.0, 3.2), r, box), segment_area(r, 0.2), 1e-14);
  EXPECT_EQ(volume_of_one<2>(vec<2>(1.0, 3.6), r, box), 0.0);
}

TEST(SolidVolumeInBox, SphereInsideAndOutside) {
  const double r = 0.3, vol = 4.0 / 3.0 * kPi * r * r * r;
  const Box<3> box{vec<3>(0.0, 0.0, 0.0), vec<3>(1.0, 1.0, 1.0)};
  EXPECT_NEAR(volume_of_one<3>(vec<3>(0.5, 0.5, 0.5), r, box), vol, 1e-15);
  EXPECT_EQ(volume_of_one<3>(vec<3>(1.5, 0.5, 0.5), r, box), 0.0);
}

// A sphere cut by one face: the sphere less the cap of height h = r - d beyond the face,
// for faces normal to each axis (x and y faces cut the slices, z faces bound them).
TEST(SolidVolumeInBox, SphereCutByOnePlane) {
  const double r = 0.3, vol = 4.0 / 3.0 * kPi * r * r * r;
  const Box<3> box{vec<3>(0.0, 0.0, 0.0), vec<3>(1.0, 1.0, 1.0)};
  for (double d : {-0.29, -0.2, -0.05, 0.0, 0.1, 0.25, 0.299}) {
    SCOPED_TRACE(d);
    const double want = vol - cap_volume(r, r - d);
    for (int k = 0; k < 3; ++k) {
      Vec<3> c = Vec<3>::Constant(0.5);
      c[k] = 1.0 - d;  // centre at distance d inside the face hi[k]
      EXPECT_LT(rel_err(volume_of_one<3>(c, r, box), want), 1e-6) << "axis " << k << " hi";
      c[k] = d;  // ... and inside the face lo[k]
      EXPECT_LT(rel_err(volume_of_one<3>(c, r, box), want), 1e-6) << "axis " << k << " lo";
    }
  }
}

TEST(SolidVolumeInBox, SphereOnFacesEdgesAndCorners) {
  const double r = 0.3, vol = 4.0 / 3.0 * kPi * r * r * r;
  const Box<3> box{vec<3>(0.0, 0.0, 0.0), vec<3>(1.0, 1.0, 1.0)};
  EXPECT_LT(rel_err(volume_of_one<3>(vec<3>(0.5, 0.5, 0.0), r, box), vol / 2.0), 1e-6);
  EXPECT_LT(rel_err(volume_of_one<3>(vec<3>(0.0, 0.5, 0.5), r, box), vol / 2.0), 1e-6);
  EXPECT_LT(rel_err(volume_of_one<3>(vec<3>(0.0, 1.0, 0.5), r, box), vol / 4.0), 1e-6);
  EXPECT_LT(rel_err(volume_of_one<3>(vec<3>(0.5, 0.0, 1.0), r, box), vol / 4.0), 1e-6);
  for (double x : {0.0, 1.0})
    for (double y : {0.0, 1.0})
      for (double z : {0.0, 1.0})
        EXPECT_LT(rel_err(volume_of_one<3>(vec<3>(x, y, z), r, box), vol / 8.0), 1e-6)
            << x << " " << y << " " << z;
}

// A slab of the sphere between two parallel faces, z in [a, b]: pi (r^2 z - z^3/3) from a to b.
TEST(SolidVolumeInBox, SphereSlabBetweenTwoFaces) {
  const double r = 0.3;
  auto prim = [r](double z) { return kPi * (r * r * z - z * z * z / 3.0); };
  for (int k = 0; k < 3; ++k) {
    Vec<3> lo = Vec<3>::Constant(-1.0), hi = Vec<3>::Constant(1.0);
    lo[k] = -0.12, hi[k] = 0.21;
    const Box<3> box{lo, hi};
    EXPECT_LT(rel_err(volume_of_one<3>(Vec<3>::Zero(), r, box), prim(0.21) - prim(-0.12)), 1e-6)
        << "axis " << k;
  }
}

// The eight octants around a random point partition space: their volumes add up to the
// sphere whatever faces and edges cut it.
TEST(SolidVolumeInBox, AdditiveOverRandomOctants) {
  const double r = 1.0, vol = 4.0 / 3.0 * kPi;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.1, 1.1);
  double worst = 0.0;
  for (int t = 0; t < 100; ++t) {
    const Vec<3> p = vec<3>(u(rng), u(rng), u(rng));
    double sum = 0.0;
    for (int oct = 0; oct < 8; ++oct) {
      Vec<3> lo, hi;
      for (int k = 0; k < 3; ++k) {
        const bool upper = (oct >> k) & 1;
        lo[k] = upper ? p[k] : -kBig;
        hi[k] = upper ? kBig : p[k];
      }
      sum += volume_of_one<3>(Vec<3>::Zero(), r, Box<3>{lo, hi});
    }
    worst = std::max(worst, rel_err(sum, vol));
  }
  report("sphere volume summed over random octants (worst of 100)", worst);
  EXPECT_LT(worst, 1e-6);
}

// Grains fully inside, cut, and outside, summed; and the porosity that follows.
template <typename T>
class SolidVolumeSum : public ::testing::Test {};
TYPED_TEST_SUITE(SolidVolumeSum, Dims, DimNames);
TYPED_TEST(SolidVolumeSum, PorosityOfHalvesAndWholes) {
  constexpr int D = TypeParam::value;
  World<D> w;
  const double r = 0.1;
  w.particles.add(vec<D>(0.5, 0.5, 0.5), r, 1000.0, 0);  // inside
  w.particles.add(vec<D>(0.0, 0.5, 0.5), r, 1000.0, 0);  // half
  w.particles.add(vec<D>(1.0, 1.0, 1.0), r, 1000.0, 0);  // quarter (2D) or eighth (3D)
  w.particles.add(vec<D>(3.0, 0.5, 0.5), r, 1000.0, 0);  // outside
  const Box<D> box{Vec<D>::Zero(), Vec<D>::Constant(1.0)};
  const double v = Dim<D>::volume(r);
  const double want = v * (1.0 + 0.5 + (D == 2 ? 0.25 : 0.125));
  EXPECT_LT(rel_err(solid_volume_in_box(w, box), want), 1e-6);
  EXPECT_LT(rel_err(porosity_in_box(w, box), 1.0 - want), 1e-6);
}

// Orientation integration (when tracked): a free grain spinning at a constant angular
// velocity w turns by |w| t about w; the quaternion stays of unit length to rounding.
TEST(Orientation, FreeSpinTurnsByOmegaTimesT) {
  World<3> w;
  add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  w.particles.add(Vec<3>::Zero(), 0.01, 2600.0, 0);
  const Eigen::Vector3d omega(0.3, -1.2, 2.0);
  w.particles.angvel[0] = omega;
  w.track_orientation = true;
  w.dt = 1e-3;
  const int steps = 5000;
  for (int k = 0; k < steps; ++k) step(w);
  const double t = steps * w.dt;
  const Eigen::Quaterniond want(Eigen::AngleAxisd(omega.norm() * t, omega.normalized()));
  const Eigen::Quaterniond& got = w.particles.orient[0];
  EXPECT_NEAR(got.norm(), 1.0, 1e-12);
  EXPECT_LT(got.angularDistance(want), 1e-9);
}

TEST(Orientation, TwoRotationsCompose) {
  // 90 degrees about x, then 90 degrees about z: the body's x axis ends along y... and
  // its z axis (turned to -y by the first rotation) ends along +x.
  World<3> w;
  add_material(w, linear_material(1e5, 5e4, 0.5, 1.0));
  w.resolve_pair_laws();
  w.particles.add(Vec<3>::Zero(), 0.01, 2600.0, 0);
  w.track_orientation = true;
  const int steps = 1000;
  w.dt = 1e-3;
  const double rate = 0.5 * std::numbers::pi / (steps * w.dt);
  w.particles.angvel[0] = Eigen::Vector3d(rate, 0.0, 0.0);
  for (int k = 0; k < steps; ++k) step(w);
  w.particles.angvel[0] = Eigen::Vector3d(0.0, 0.0, rate);
  for (int k = 0; k < steps; ++k) step(w);
  const Eigen::Quaterniond& q = w.particles.orient[0];
  EXPECT_LT((q * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-9);
  EXPECT_LT((q * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 1e-9);
}

}  // namespace
}  // namespace geodem::test
