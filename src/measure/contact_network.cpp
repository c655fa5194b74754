#include "measure/contact_network.hpp"

#include <Eigen/Eigenvalues>

#include "contacts/contact_law.hpp"

namespace geodem {

namespace {

// Calls f(i, j, list entry, normal, overlap, bonded) for each grain-grain contact touching or
// bonded. In a decomposed world a contact across a rank boundary is listed on both ranks: the
// rank that owns its row's grain has it (rows of ghosts are skipped).
template <int D, class F>
void each_contact(const World<D>& w, F&& f) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = w.particles;
  const auto& L = w.nlist;
  const bool extras = !L.extra.empty();
  for (std::size_t i = 0; i + 1 < L.start.size(); ++i) {
    if (P.flags[i] & kGhost) continue;
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const std::uint32_t j = L.other[k];
      const Vec d = w.branch(i, j, k);
      const double dist = d.norm(), rs = P.radius[i] + P.radius[j];
      const bool bond = extras && L.extra[k].bonded;
      if ((dist >= rs && !bond) || dist <= 0.0) continue;
      f(i, j, k, Vec(d / dist), rs - dist, bond);
    }
  }
}

}  // namespace

template <int D>
ContactNetwork<D> contact_network(const World<D>& w) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = w.particles;
  ContactNetwork<D> c;
  each_contact(w, [&](std::size_t i, std::uint32_t j, std::uint32_t k, const Vec& n, double delta,
                      bool bond) {
    const PairLaw& law = w.pair_law(P.material[i], P.material[j]);
    c.i.push_back(static_cast<std::uint32_t>(i));
    c.j.push_back(j);
    c.normal.push_back(n);
    c.overlap.push_back(delta);
    c.normal_force.push_back(bond || delta <= 0.0
                                 ? law.linear_kn(P.radius[i], P.radius[j]) * delta
                                 : normal_force(law, P.radius[i], P.radius[j], 0.0, delta, 0.0).fn);
    c.tangential_force.push_back(tangential_force<D>(w.nlist.spring[k], n));
    c.bonded.push_back(bond ? 1 : 0);
  });
  return c;
}

template <int D>
WallContacts<D> wall_contacts(const World<D>& w) {
  using Vec = typename Dim<D>::Vec;
  const auto& P = w.particles;
  const auto& L = w.nlist;
  WallContacts<D> c;
  for (std::size_t i = 0; i + 1 < L.wall_start.size(); ++i)
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      const double r = P.radius[i];
      Vec n;
      double delta;
      if (!wall_overlap(w.walls[L.wall[k]], P.pos[i], r, n, delta)) continue;
      const PairLaw& law = w.wall_law(P.material[i], L.wall[k]);
      c.grain.push_back(static_cast<std::uint32_t>(i));
      c.wall.push_back(L.wall[k]);
      c.normal.push_back(n);
      c.overlap.push_back(delta);
      c.normal_force.push_back(
          normal_force(law, r, wall_partner_radius(law, r), 0.0, delta, 0.0).fn);
      c.tangential_force.push_back(tangential_force<D>(L.wall_spring[k], n));
    }
  return c;
}

template <int D>
typename Dim<D>::Tensor fabric_tensor(const World<D>& w) {
  using Vec = typename Dim<D>::Vec;
  typename Dim<D>::Tensor f = Dim<D>::Tensor::Zero();
  std::size_t count = 0;
  if (w.domain) {
    // A decomposed world: each rank's contacts in exact sums added over ranks (the same bits
    // for any number of ranks).
    std::vector<ExactSum> s(D * D + 1);
    each_contact(w,
                 [&](std::size_t, std::uint32_t, std::uint32_t, const Vec& n, double delta, bool) {
                   if (delta <= 0.0) return;
                   for (int a = 0; a < D; ++a)
                     for (int b = 0; b < D; ++b) s[a * D + b].add(n[a] * n[b]);
                   s[D * D].add(1.0);
                 });
    w.domain->sum(s);
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) f(a, b) = s[a * D + b].value();
    count = static_cast<std::size_t>(s[D * D].value());
  } else {
    each_contact(w,
                 [&](std::size_t, std::uint32_t, std::uint32_t, const Vec& n, double delta, bool) {
                   if (delta <= 0.0) return;  // a bond held open is not a contact of the fabric
                   f += n * n.transpose();
                   ++count;
                 });
  }
  return count ? typename Dim<D>::Tensor(f / static_cast<double>(count)) : f;
}

template <int D>
double fabric_anisotropy(const typename Dim<D>::Tensor& fabric) {
  if (fabric.isZero()) return 0.0;
  Eigen::SelfAdjointEigenSolver<typename Dim<D>::Tensor> eig(fabric, Eigen::EigenvaluesOnly);
  return D * (eig.eigenvalues().maxCoeff() - eig.eigenvalues().minCoeff());
}

template ContactNetwork<2> contact_network<2>(const World<2>&);
template ContactNetwork<3> contact_network<3>(const World<3>&);
template WallContacts<2> wall_contacts<2>(const World<2>&);
template WallContacts<3> wall_contacts<3>(const World<3>&);
template Dim<2>::Tensor fabric_tensor<2>(const World<2>&);
template Dim<3>::Tensor fabric_tensor<3>(const World<3>&);
template double fabric_anisotropy<2>(const Dim<2>::Tensor&);
template double fabric_anisotropy<3>(const Dim<3>::Tensor&);

}  // namespace geodem
