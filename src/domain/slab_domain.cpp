#include "domain/slab_domain.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "base/error.hpp"
#include "broadphase/list_history.hpp"

namespace geodem {

namespace {

template <int D>
bool loaded(const TangentSpring<D>& s, const ContactExtra<D>& e) {
  return !zero_bits(s) || e.bonded != 0 || !zero_bits(e.roll) || !zero_bits(e.twist);
}

// The history of list entry (grain i, partner j) keyed by ids, a < b. The list keeps the
// spring as seen by the row's grain; seen from the other grain a 3D spring and the rolling
// moment change sign (as when grains are renumbered, broadphase/neighbour_search.cpp).
template <int D>
PairRecord<D> pair_record(std::uint32_t id_i, std::uint32_t id_j, const TangentSpring<D>& s,
                          const ContactExtra<D>& e) {
  PairRecord<D> r{id_i, id_j, s, e};
  if (id_i > id_j) {
    r.a = id_j, r.b = id_i;
    r.spring = spring_from_other_body<D>(s);
    r.extra.roll = -e.roll;
  }
  return r;
}

template <int D>
void resize_grains(Particles<D>& P, std::size_t n) {
  P.pos.resize(n), P.vel.resize(n), P.angvel.resize(n), P.force.resize(n), P.torque.resize(n);
  P.radius.resize(n), P.inv_mass.resize(n), P.inv_inertia.resize(n), P.material.resize(n);
  P.flags.resize(n), P.pos_at_build.resize(n), P.id.resize(n);
  if (!P.orient.empty()) P.orient.resize(n);
}

// Local index of a grain id (the rank's grains are sorted by id), or -1.
template <int D>
std::int64_t find_id(const Particles<D>& P, std::uint32_t id) {
  const auto it = std::lower_bound(P.id.begin(), P.id.end(), id);
  return it != P.id.end() && *it == id ? it - P.id.begin() : -1;
}

bool contains(const std::vector<std::uint32_t>& sorted, std::uint32_t id) {
  return std::binary_search(sorted.begin(), sorted.end(), id);
}

}  // namespace

template <int D>
std::shared_ptr<SlabDomain<D>> SlabDomain<D>::distribute(World<D>& world,
                                                         std::shared_ptr<DomainComm> comm) {
  auto refuse = [](const std::string& what) {
    throw InputError("", 0, "", what + " (docs/parallel.md)");
  };
  if (world.clumps.size() > 0) refuse("clumps are not distributed over ranks yet");
  if (!world.spars.empty()) refuse("spar chains are not distributed over ranks yet");
  if (world.cell.periodic) refuse("a periodic cell is not distributed over ranks yet");
  auto d = std::shared_ptr<SlabDomain>(new SlabDomain(std::move(comm)));
  auto& P = world.particles;
  const std::size_t n = P.size();
  const int ranks = d->comm_->size(), me = d->comm_->rank();
  double rmax = 0.0;
  ExactSum radii;  // the same skin on every rank, whatever order the grains are in
  for (std::size_t i = 0; i < n; ++i) rmax = std::max(rmax, P.radius[i]), radii.add(P.radius[i]);
  d->skin_ = n > 0 ? world.skin_factor * radii.value() / static_cast<double>(n) : 0.0;
  d->ghost_width_ = 2.0 * rmax + d->skin_;
  // Cuts at equal grain counts along x.
  std::vector<double> xs(n);
  for (std::size_t i = 0; i < n; ++i) xs[i] = P.pos[i].x();
  std::sort(xs.begin(), xs.end());
  const double inf = std::numeric_limits<double>::infinity();
  d->cuts_.assign(static_cast<std::size_t>(ranks) + 1, -inf);
  d->cuts_.back() = inf;
  for (int q = 1; q < ranks; ++q)
    d->cuts_[static_cast<std::size_t>(q)] =
        n > 0 ? xs[static_cast<std::size_t>(q) * n / static_cast<std::size_t>(ranks)] : 0.0;
  // A grain moves less than the skin between builds, and ghosts come from the next slab only:
  // the inner slabs must be at least a ghost width across.
  for (std::size_t q = 1; q + 2 < d->cuts_.size(); ++q)
    if (d->cuts_[q + 1] - d->cuts_[q] < d->ghost_width_)
      refuse(std::to_string(ranks) + " ranks cut the grains into slabs " +
             std::to_string(d->cuts_[q + 1] - d->cuts_[q]) + " m wide, less than the ghost width " +
             std::to_string(d->ghost_width_) + " m (2 x largest radius + skin): use fewer ranks");
  d->collect_history(world);
  std::vector<std::uint32_t> mine;
  for (std::size_t i = 0; i < n; ++i)
    if (d->owner(P.pos[i].x()) == me) mine.push_back(static_cast<std::uint32_t>(i));
  std::sort(mine.begin(), mine.end(), [&](auto a, auto b) { return P.id[a] < P.id[b]; });
  P.permute(mine);
  NeighbourList<D> none;
  world.nlist.swap_rows(none);
  world.one_slab = true;
  world.sort_interval = 0;  // grains stay in id order
  world.rebuild_needed = true;
  world.domain = d;
  return d;
}

template <int D>
int SlabDomain<D>::owner(double x) const {
  const auto it = std::upper_bound(cuts_.begin() + 1, cuts_.end() - 1, x);
  return static_cast<int>(it - (cuts_.begin() + 1));
}

template <int D>
std::size_t SlabDomain<D>::owned(const World<D>& world) const {
  const auto& f = world.particles.flags;
  return static_cast<std::size_t>(
      std::count_if(f.begin(), f.end(), [](std::uint8_t v) { return !(v & kGhost); }));
}

template <int D>
bool SlabDomain<D>::any_rank(bool here) {
  return comm_->max(here ? 1.0 : 0.0) > 0.5;
}

template <int D>
double SlabDomain<D>::min_over_ranks(double here) {
  return comm_->min(here);
}

template <int D>
void SlabDomain<D>::collect_history(const World<D>& world) {
  const auto& P = world.particles;
  const auto& L = world.nlist;
  const std::size_t n = P.size();
  if (L.start.size() != n + 1) return;
  const bool extras = !L.extra.empty() && L.extra.size() == L.other.size();
  const bool wall_extras = !L.wall_extra.empty() && L.wall_extra.size() == L.wall.size();
  const ContactExtra<D> none{};
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      const ContactExtra<D>& e = extras ? L.extra[k] : none;
      if (loaded<D>(L.spring[k], e))
        pairs_.push_back(pair_record<D>(P.id[i], P.id[L.other[k]], L.spring[k], e));
    }
    if (L.wall_start.size() != n + 1) continue;
    for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
      const ContactExtra<D>& e = wall_extras ? L.wall_extra[k] : none;
      if (loaded<D>(L.wall_spring[k], e))
        walls_.push_back({P.id[i], L.wall[k], L.wall_spring[k], e});
    }
  }
}

template <int D>
void SlabDomain<D>::before_build(World<D>& world) {
  auto& P = world.particles;
  const int me = comm_->rank(), ranks = comm_->size();
  collect_history(world);
  // Owned grains that stay, and those that left for a neighbour's slab with their history.
  std::vector<GrainRecord<D>> keep, down, up;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.flags[i] & kGhost) continue;
    const int to = owner(P.pos[i].x());
    if (to == me) {
      keep.push_back(GrainRecord<D>::of(P, i));
    } else if (to == me - 1 || to == me + 1) {
      (to < me ? down : up).push_back(GrainRecord<D>::of(P, i));
    } else {
      throw InstabilityError("grain " + std::to_string(P.id[i]) +
                             " crossed a whole rank's slab (x = " + std::to_string(P.pos[i].x()) +
                             " m) between two neighbour-list " +
                             "builds; likely cause: a runaway grain, or slabs too thin");
    }
  }
  auto migration = [&](const std::vector<GrainRecord<D>>& grains) {
    std::vector<std::uint32_t> ids;
    for (const auto& g : grains) ids.push_back(g.id);
    std::sort(ids.begin(), ids.end());
    std::vector<PairRecord<D>> pairs;
    std::vector<WallRecord<D>> walls;
    for (const auto& p : pairs_)
      if (contains(ids, p.a) || contains(ids, p.b)) pairs.push_back(p);
    for (const auto& w : walls_)
      if (contains(ids, w.id)) walls.push_back(w);
    Bytes b;
    put_records(b, grains);
    put_records(b, pairs);
    put_records(b, walls);
    return b;
  };
  Bytes to_lower = migration(down), to_upper = migration(up), from_lower, from_upper;
  comm_->exchange(to_lower, to_upper, from_lower, from_upper);
  build_bytes_ = to_lower.size() + to_upper.size();
  for (const Bytes* in : {&from_lower, &from_upper}) {
    if (in->empty()) continue;
    std::size_t at = 0;
    for (const auto& g : take_records<GrainRecord<D>>(*in, at)) keep.push_back(g);
    for (const auto& p : take_records<PairRecord<D>>(*in, at)) pairs_.push_back(p);
    for (const auto& w : take_records<WallRecord<D>>(*in, at)) walls_.push_back(w);
  }
  std::sort(keep.begin(), keep.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  // Ghosts: this rank's grains within the ghost width of a neighbour's slab, in id order.
  std::vector<GrainRecord<D>> ghost_down, ghost_up;
  for (const auto& g : keep) {
    if (me > 0 && g.pos.x() < cuts_[static_cast<std::size_t>(me)] + ghost_width_)
      ghost_down.push_back(g);
    if (me + 1 < ranks && g.pos.x() >= cuts_[static_cast<std::size_t>(me) + 1] - ghost_width_)
      ghost_up.push_back(g);
  }
  to_lower.clear(), to_upper.clear();
  put_records(to_lower, ghost_down);
  put_records(to_upper, ghost_up);
  comm_->exchange(to_lower, to_upper, from_lower, from_upper);
  build_bytes_ += to_lower.size() + to_upper.size();
  std::vector<GrainRecord<D>> ghosts_from_lower, ghosts_from_upper;
  if (!from_lower.empty()) {
    std::size_t at = 0;
    ghosts_from_lower = take_records<GrainRecord<D>>(from_lower, at);
  }
  if (!from_upper.empty()) {
    std::size_t at = 0;
    ghosts_from_upper = take_records<GrainRecord<D>>(from_upper, at);
  }
  // The rank's grains and ghosts, by id.
  std::vector<GrainRecord<D>> all = keep;
  for (auto* gs : {&ghosts_from_lower, &ghosts_from_upper})
    for (auto g : *gs) {
      g.flags |= kGhost;
      all.push_back(g);
    }
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  resize_grains(P, all.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i].store(P, i);
  auto where = [&](const std::vector<GrainRecord<D>>& gs, std::vector<std::uint32_t>& idx) {
    idx.clear();
    for (const auto& g : gs) idx.push_back(static_cast<std::uint32_t>(find_id(P, g.id)));
  };
  where(ghost_down, send_lower_), where(ghost_up, send_upper_);
  where(ghosts_from_lower, recv_lower_), where(ghosts_from_upper, recv_upper_);
  rewrite_rows(world);
  pairs_.clear(), walls_.clear();
}

template <int D>
void SlabDomain<D>::rewrite_rows(World<D>& world) const {
  const auto& P = world.particles;
  auto& L = world.nlist;
  const std::size_t n = P.size();
  auto pairs = pairs_;
  auto walls = walls_;
  auto by_pair = [](const auto& x, const auto& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; };
  std::sort(pairs.begin(), pairs.end(), by_pair);
  // A contact's history arrives from every rank that held it: the copies are the same bits.
  pairs.erase(std::unique(pairs.begin(), pairs.end(),
                          [](const auto& x, const auto& y) { return x.a == y.a && x.b == y.b; }),
              pairs.end());
  auto by_wall = [](const auto& x, const auto& y) {
    return x.id != y.id ? x.id < y.id : x.wall < y.wall;
  };
  std::sort(walls.begin(), walls.end(), by_wall);
  walls.erase(
      std::unique(walls.begin(), walls.end(),
                  [](const auto& x, const auto& y) { return x.id == y.id && x.wall == y.wall; }),
      walls.end());
  const bool extras = world.contact_extras;
  NeighbourList<D> rows;
  rows.start.assign(n + 1, 0);
  rows.wall_start.assign(n + 1, 0);
  // Records sorted by (a, b) and grains by id: rows come out in order, each sorted by partner.
  for (const auto& p : pairs) {
    const std::int64_t i = find_id(P, p.a), j = find_id(P, p.b);
    if (i < 0 || j < 0) continue;
    const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j);
    if ((P.flags[ui] & kGhost) && (P.flags[uj] & kGhost)) continue;
    ++rows.start[ui + 1];
    rows.other.push_back(static_cast<std::uint32_t>(uj));
    rows.spring.push_back(p.spring);
    if (extras) rows.extra.push_back(p.extra);
  }
  for (const auto& w : walls) {
    const std::int64_t i = find_id(P, w.id);
    if (i < 0 || (P.flags[static_cast<std::size_t>(i)] & kGhost)) continue;
    ++rows.wall_start[static_cast<std::size_t>(i) + 1];
    rows.wall.push_back(w.wall);
    rows.wall_spring.push_back(w.spring);
    if (extras) rows.wall_extra.push_back(w.extra);
  }
  for (std::size_t i = 0; i < n; ++i) {
    rows.start[i + 1] += rows.start[i];
    rows.wall_start[i + 1] += rows.wall_start[i];
  }
  L.swap_rows(rows);
}

template <int D>
void SlabDomain<D>::after_integration(World<D>& world) {
  auto& P = world.particles;
  const bool track = !P.orient.empty();
  auto pack = [&](const std::vector<std::uint32_t>& idx, Bytes& out) {
    out.resize(idx.size() * sizeof(GhostState<D>));
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const std::uint32_t i = idx[k];
      const GhostState<D> g{P.pos[i], P.vel[i], P.angvel[i],
                            track ? P.orient[i] : Dim<D>::identity()};
      std::memcpy(out.data() + k * sizeof g, static_cast<const void*>(&g), sizeof g);
    }
  };
  auto unpack = [&](const Bytes& in, const std::vector<std::uint32_t>& idx) {
    if (in.size() != idx.size() * sizeof(GhostState<D>))
      throw std::runtime_error("ghost update of " + std::to_string(in.size()) + " bytes for " +
                               std::to_string(idx.size()) + " ghosts");
    for (std::size_t k = 0; k < idx.size(); ++k) {
      GhostState<D> g;
      std::memcpy(static_cast<void*>(&g), in.data() + k * sizeof g, sizeof g);
      const std::uint32_t i = idx[k];
      P.pos[i] = g.pos, P.vel[i] = g.vel, P.angvel[i] = g.angvel;
      if (track) P.orient[i] = g.orient;
    }
  };
  pack(send_lower_, halo_out_lower_);
  pack(send_upper_, halo_out_upper_);
  comm_->exchange(halo_out_lower_, halo_out_upper_, halo_in_lower_, halo_in_upper_);
  unpack(halo_in_lower_, recv_lower_);
  unpack(halo_in_upper_, recv_upper_);
  halo_bytes_ = halo_out_lower_.size() + halo_out_upper_.size();
}

template class SlabDomain<2>;
template class SlabDomain<3>;

}  // namespace geodem
