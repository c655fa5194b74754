#include "clumps/clump_template.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geodem {

namespace {

// Moments of a union of intervals along one axis: integrals of 1, t and t^2.
struct Moments1 {
  double m0 = 0.0, m1 = 0.0, m2 = 0.0;
};

// Merges the intervals (sorted here) and integrates 1, t, t^2 over their union exactly.
Moments1 union_moments(std::vector<std::pair<double, double>>& iv) {
  Moments1 m;
  if (iv.empty()) return m;
  std::sort(iv.begin(), iv.end());
  auto add = [&m](double a, double b) {
    m.m0 += b - a;
    m.m1 += 0.5 * (b * b - a * a);
    m.m2 += (b * b * b - a * a * a) / 3.0;
  };
  double a = iv[0].first, b = iv[0].second;
  for (std::size_t k = 1; k < iv.size(); ++k) {
    if (iv[k].first > b) {
      add(a, b);
      a = iv[k].first;
      b = iv[k].second;
    } else {
      b = std::max(b, iv[k].second);
    }
  }
  add(a, b);
  return m;
}

}  // namespace

// Column integration. The union is cut into columns parallel to the last axis (y in
// 2D, z in 3D); in each column the members' chords are intervals whose union is
// integrated exactly, and the columns are summed with the midpoint rule. The error comes
// from the columns that cross a member's edge, where the chord length behaves as the
// square root of the distance: it falls as h^1.5 with the column width h, i.e. about
// 1e-7 (2D, 1e5 columns) and 1e-5 (3D, 1000 x 1000 columns) relative, with most of it
// cancelling between the two sides of each edge.
template <int D>
MassProperties<D> union_mass_properties(const std::vector<typename Dim<D>::Vec>& centre,
                                        const std::vector<double>& radius, int columns) {
  using Vec = typename Dim<D>::Vec;
  using Tensor = typename Dim<D>::Tensor;
  if (centre.empty() || centre.size() != radius.size())
    throw std::invalid_argument("a clump needs at least one member, each with a radius");
  if (columns <= 0) columns = D == 2 ? 100000 : 1000;
  Vec lo = centre[0] - Vec::Constant(radius[0]), hi = centre[0] + Vec::Constant(radius[0]);
  for (std::size_t m = 0; m < centre.size(); ++m) {
    if (!(radius[m] > 0.0)) throw std::invalid_argument("clump member radii must be positive");
    lo = lo.cwiseMin(centre[m] - Vec::Constant(radius[m]));
    hi = hi.cwiseMax(centre[m] + Vec::Constant(radius[m]));
  }
  const double h = (hi - lo).head(D - 1).maxCoeff() / columns;
  // Raw sums: integrals of 1, x_k, x_k x_l over the union.
  double vol = 0.0;
  Vec first = Vec::Zero();
  Tensor second = Tensor::Zero();
  std::vector<std::pair<double, double>> iv;
  const int last = D - 1;
  std::array<int, 2> count{1, 1};
  for (int k = 0; k < D - 1; ++k)
    count[static_cast<std::size_t>(k)] = static_cast<int>(std::ceil((hi[k] - lo[k]) / h));
  for (int a = 0; a < count[0]; ++a) {
    for (int b = 0; b < count[1]; ++b) {
      Vec x = Vec::Zero();
      x[0] = lo[0] + (a + 0.5) * h;
      if constexpr (D == 3) x[1] = lo[1] + (b + 0.5) * h;
      iv.clear();
      for (std::size_t m = 0; m < centre.size(); ++m) {
        double rho2 = 0.0;
        for (int k = 0; k < D - 1; ++k) rho2 += (x[k] - centre[m][k]) * (x[k] - centre[m][k]);
        const double c2 = radius[m] * radius[m] - rho2;
        if (c2 <= 0.0) continue;
        const double half = std::sqrt(c2);
        iv.emplace_back(centre[m][last] - half, centre[m][last] + half);
      }
      if (iv.empty()) continue;
      const Moments1 mt = union_moments(iv);
      const double w = std::pow(h, D - 1);
      vol += w * mt.m0;
      for (int k = 0; k < D - 1; ++k) {
        first[k] += w * x[k] * mt.m0;
        second(last, k) += w * x[k] * mt.m1;
        for (int l = 0; l < D - 1; ++l) second(k, l) += w * x[k] * x[l] * mt.m0;
      }
      first[last] += w * mt.m1;
      second(last, last) += w * mt.m2;
    }
  }
  for (int k = 0; k < D - 1; ++k) second(k, last) = second(last, k);
  MassProperties<D> p;
  p.volume = vol;
  p.centroid = first / vol;
  // Second moment about the centroid (parallel axis theorem).
  const Tensor s = second - vol * p.centroid * p.centroid.transpose();
  p.inertia = D == 2 ? s : Tensor(s.trace() * Tensor::Identity() - s);
  return p;
}

template <int D>
ResolvedClump<D> resolve_clump(const ClumpTemplate<D>& t) {
  using Vec = typename Dim<D>::Vec;
  const MassProperties<D> p = union_mass_properties<D>(t.centre, t.radius);
  ResolvedClump<D> r;
  r.name = t.name;
  r.volume = p.volume;
  r.radius = t.radius;
  if constexpr (D == 2) {
    // In 2D `inertia` holds the second-moment matrix: the polar moment is its trace.
    r.principal = p.inertia.trace();
    for (const Vec& c : t.centre) r.offset.push_back(c - p.centroid);
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(p.inertia);
    Eigen::Matrix3d axes = eig.eigenvectors();
    if (axes.determinant() < 0.0) axes.col(2) *= -1.0;  // a proper rotation
    r.principal = eig.eigenvalues();
    for (const Vec& c : t.centre) r.offset.push_back(axes.transpose() * (c - p.centroid));
  }
  for (std::size_t m = 0; m < r.offset.size(); ++m)
    r.bounding_radius = std::max(r.bounding_radius, r.offset[m].norm() + r.radius[m]);
  return r;
}

template <int D>
bool builtin_clump_template(const std::string& name, ClumpTemplate<D>& out) {
  using Vec = typename Dim<D>::Vec;
  out = ClumpTemplate<D>{};
  out.name = name;
  if (name == "sphere" || name == "disc") {
    out.centre = {Vec::Zero()};
    out.radius = {1.0};
  } else if (name == "pair") {
    out.centre = {Vec::Zero(), Vec::Unit(0) * 2.0};
    out.radius = {1.0, 1.0};
  } else if (name == "pair_0.9") {
    out.centre = {Vec::Zero(), Vec::Unit(0) * 1.9};
    out.radius = {1.0, 0.9};
  } else {
    return false;
  }
  return true;
}

std::vector<std::string> builtin_clump_template_names() {
  return {"sphere", "disc", "pair", "pair_0.9"};
}

template MassProperties<2> union_mass_properties<2>(const std::vector<Dim<2>::Vec>&,
                                                    const std::vector<double>&, int);
template MassProperties<3> union_mass_properties<3>(const std::vector<Dim<3>::Vec>&,
                                                    const std::vector<double>&, int);
template ResolvedClump<2> resolve_clump<2>(const ClumpTemplate<2>&);
template ResolvedClump<3> resolve_clump<3>(const ClumpTemplate<3>&);
template bool builtin_clump_template<2>(const std::string&, ClumpTemplate<2>&);
template bool builtin_clump_template<3>(const std::string&, ClumpTemplate<3>&);

}  // namespace geodem
