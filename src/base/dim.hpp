// Dimension traits: one code path for 2D discs and 3D spheres.
// In 2D a grain has 3 degrees of freedom (x, y, rotation angle); in 3D it has 6
// (position, orientation quaternion). `Rot` is the type of angular quantities:
// a scalar about the out-of-plane axis in 2D, a vector in 3D.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <type_traits>

namespace geodem {

template <int D>
struct Dim;

template <>
struct Dim<2> {
  using Vec = Eigen::Vector2d;
  using Rot = double;     // angular velocity, torque about z
  using Orient = double;  // rotation angle (rad)
  using Tensor = Eigen::Matrix2d;
  static constexpr int rot_dofs = 1;
  // Per metre of out-of-plane thickness.
  static double volume(double r) { return std::numbers::pi * r * r; }
  static double inertia_factor() { return 0.5; }  // I = 1/2 m r^2 (disc)
  static Rot zero_rot() { return 0.0; }
  static Orient identity() { return 0.0; }
  static Vec cross(Rot w, const Vec& r) { return Vec(-w * r.y(), w * r.x()); }
  static Rot cross(const Vec& a, const Vec& b) { return a.x() * b.y() - a.y() * b.x(); }
  static double rot_norm2(Rot w) { return w * w; }
  static void rotate(Orient& q, Rot w, double dt) { q += w * dt; }
};

template <>
struct Dim<3> {
  using Vec = Eigen::Vector3d;
  using Rot = Eigen::Vector3d;
  using Orient = Eigen::Quaterniond;
  using Tensor = Eigen::Matrix3d;
  static constexpr int rot_dofs = 3;
  static double volume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }
  static double inertia_factor() { return 0.4; }  // I = 2/5 m r^2 (sphere)
  static Rot zero_rot() { return Rot::Zero(); }
  static Orient identity() { return Orient::Identity(); }
  // Rot and Vec are the same type in 3D: one cross product serves both uses.
  static Vec cross(const Vec& a, const Vec& b) { return a.cross(b); }
  static double rot_norm2(const Rot& w) { return w.squaredNorm(); }
  // Rotation by the angle |w| dt about w (world frame). Small angles (the usual
  // case: |w| dt is tiny) use the Taylor series of sin and cos, exact to double
  // precision below 1e-2 rad and much cheaper than the library calls. The product of
  // two unit quaternions drifts from unit length only by rounding: one Newton step
  // towards |q| = 1 (no square root, no division) keeps it there.
  static void rotate(Orient& q, const Rot& w, double dt) {
    const double w2 = w.squaredNorm();
    if (w2 == 0.0) return;
    const double a2 = w2 * dt * dt;  // angle^2
    double c, s_over_angle;          // cos(angle/2), sin(angle/2)/angle
    if (a2 < 1e-4) {
      c = 1.0 + a2 * (-1.0 / 8.0 + a2 * (1.0 / 384.0));
      s_over_angle = 0.5 + a2 * (-1.0 / 48.0 + a2 * (1.0 / 3840.0));
    } else {
      const double angle = std::sqrt(a2);
      c = std::cos(0.5 * angle);
      s_over_angle = std::sin(0.5 * angle) / angle;
    }
    const Eigen::Vector3d v = (s_over_angle * dt) * w;
    q = Eigen::Quaterniond(c, v.x(), v.y(), v.z()) * q;
    q.coeffs() *= 1.5 - 0.5 * q.squaredNorm();
  }
};

// An array of D-vectors (Eigen's fixed sizes hold their coefficients and nothing else) or of
// doubles, seen as its doubles (the vector kernels read the grains' arrays so).
template <typename T>
auto* as_doubles(T* p) {
  if constexpr (std::is_arithmetic_v<std::remove_const_t<T>>) {
    return p;
  } else {
    static_assert(sizeof(T) == T::SizeAtCompileTime * sizeof(double));
    return p == nullptr ? nullptr : p->data();
  }
}

}  // namespace geodem
