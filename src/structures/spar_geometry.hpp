// Where a grain touches a spar chain: the closest point of an element, and which
// element owns it. The rule counts every contact once:
// - a grain whose projection falls inside an element's span touches that element;
// - near a node shared by two elements, the element that starts there owns the node,
//   and only while the grain lies beyond the end of the previous element too (the
//   node's own region); otherwise the previous element's interior point is closer;
// - the free ends of a chain are rounded caps, owned by their element.
// On the concave side of a bend a grain can touch both elements inside their spans:
// those are two genuine contacts. A contact that leaves an element's span for its
// neighbour's is handed over with its tangential spring (spar_contacts.cpp).
#pragma once

#include <algorithm>

#include "structures/spar_chains.hpp"

namespace geodem {

enum class SparRegion : std::uint8_t {
  kOwned,   // this element holds the contact
  kToNext,  // the point belongs to the next element (beyond this element's end)
  kToPrev,  // the point lies inside the previous element's span
};

template <int D>
struct SparPoint {
  typename Dim<D>::Vec closest;  // on the element's axis
  double t = 0.0;                // 0 at node_a, 1 at node_b (clamped)
  SparRegion region = SparRegion::kOwned;
};

// Parameter of the projection of x on element e's line (not clamped).
template <int D>
inline double spar_parameter(const SparChains<D>& S, std::size_t e, const typename Dim<D>::Vec& x) {
  const auto& a = S.pos[S.node_a[e]];
  const typename Dim<D>::Vec seg = S.pos[S.node_b[e]] - a;
  const double len2 = seg.squaredNorm();
  return len2 > 0.0 ? (x - a).dot(seg) / len2 : 0.0;  // a folded element is a point
}

template <int D>
inline SparPoint<D> spar_point(const SparChains<D>& S, std::size_t e,
                               const typename Dim<D>::Vec& x) {
  SparPoint<D> p;
  const double t = spar_parameter(S, e, x);
  if (t >= 1.0 && S.next[e] != kNoElement) {
    p.region = SparRegion::kToNext;
  } else if (t < 0.0 && S.prev[e] != kNoElement &&
             spar_parameter(S, static_cast<std::size_t>(S.prev[e]), x) < 1.0) {
    p.region = SparRegion::kToPrev;
  }
  p.t = std::clamp(t, 0.0, 1.0);
  p.closest = (1.0 - p.t) * S.pos[S.node_a[e]] + p.t * S.pos[S.node_b[e]];
  return p;
}

}  // namespace geodem
