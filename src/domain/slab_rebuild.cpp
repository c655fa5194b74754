// A decomposed domain before each neighbour-list build (domain/slab_domain.hpp): grains that
// left their slab go to the neighbour, ghosts are renewed, the rank's grains are put in key
// order, and the list's rows are carried into the new numbering so that the build merges
// their history as on one process.
//
// Memory: the grains are reordered one array at a time and the rows rewritten once, as a
// one-process build renumbers them (broadphase/neighbour_search.cpp); only the grains that
// change ranks travel as records with their history.
#include <algorithm>
#include <limits>
#include <string>
#include <tuple>

#include "base/error.hpp"
#include "base/heap_trim.hpp"
#include "broadphase/list_history.hpp"
#include "broadphase/periodic_search.hpp"
#include "domain/slab_domain.hpp"

namespace geodem {

namespace {

bool contains(const std::vector<std::uint32_t>& sorted, std::uint32_t id) {
  return std::binary_search(sorted.begin(), sorted.end(), id);
}

}  // namespace

// Radius growth (the triaxial compaction) widens the reach of a contact: the skin follows the
// whole domain's mean radius and the ghost width its largest grain (and clump member offset),
// taken alike on every rank, so the keys' grid (cells a ghost width across) is the same for
// any number of ranks.
template <int D>
void SlabDomain<D>::follow_grain_growth(const World<D>& world) {
  const auto& P = world.particles;
  double rmax = 0.0, offset = 0.0;
  std::vector<ExactSum> radii(2);  // their sum and count: the skin, as one process takes it
  for (std::size_t i = 0; i < P.size(); ++i)
    if (!(P.flags[i] & kGhost)) {
      rmax = std::max(rmax, P.radius[i]);
      radii[0].add(P.radius[i]), radii[1].add(1.0);
      if (clumped_ && P.clump[i] != kNoClump) offset = std::max(offset, P.body_offset[i].norm());
    }
  rmax = comm_->max(rmax);
  // The skin follows the mean radius as one process's does (a skin kept from a loose cloud's
  // small grains rebuilt the list twice as often through a compaction).
  comm_->sum(radii);
  if (radii[1].value() > 0.0) skin_ = world.skin_factor * radii[0].value() / radii[1].value();
  if (clumped_ && extent_ > 0.0) extent_ = std::max(extent_, comm_->max(offset) + 0.5 * skin_);
  const double width = 2.0 * rmax + skin_ + extent_;
  if (!(width > ghost_width_)) return;
  ghost_width_ = width;
  refuse_thin_slabs("the grains grew to a ghost width of " + std::to_string(ghost_width_) + " m");
}

template <int D>
void SlabDomain<D>::before_build(World<D>& world) {
  auto& P = world.particles;
  const int me = comm_->rank(), ranks = comm_->size();
  const std::size_t n_old = P.size();
  // (builds counted from the distribution: every rank builds together, so the same count)
  if (rebalance_every > 0 && ranks > 1 && ++builds_since_rebalance_ > rebalance_every) {
    rebalance(world);
    builds_since_rebalance_ = 1;
  }
  // A periodic cell: the grains back into it, and the slabs' widths as the cell is now (it
  // deforms: one that shrank below the ghost width is refused like grains that grew).
  if (periodic_) {
    wrap_into_cell(world);
    take_cell(world);
    refuse_thin_slabs("the periodic cell narrowed to " + std::to_string(width_) + " m across x");
  }
  follow_grain_growth(world);
  // Every sort_interval builds (counted alike on every rank) each owner retakes its grains'
  // keys from their cells now: neighbours then sit close in memory, as on one process. The
  // grid is taken anew over the whole domain's grains (a deposit that settled to the bottom
  // of its first box would otherwise crowd into a few blocks of keys, and so a few slabs).
  if (sort_every_ > 0 && world.nlist.builds % static_cast<std::uint64_t>(sort_every_) == 0) {
    using Vec = typename Dim<D>::Vec;
    const double inf = std::numeric_limits<double>::infinity();
    Vec lo = Vec::Constant(inf), hi = Vec::Constant(-inf);
    for (std::size_t i = 0; i < n_old; ++i)
      if (!(P.flags[i] & kGhost)) lo = lo.cwiseMin(P.pos[i]), hi = hi.cwiseMax(P.pos[i]);
    for (int k = 0; k < D; ++k) lo[k] = comm_->min(lo[k]), hi[k] = comm_->max(hi[k]);
    std::vector<ExactSum> count(1);
    count[0].add(static_cast<double>(owned(world)));
    comm_->sum(count);
    const auto grains = static_cast<std::uint64_t>(count[0].value());
    if (grains > 0) set_grid(lo, hi, grains, key_block_ == 0);
    for (std::size_t i = 0; i < n_old; ++i)
      if (!(P.flags[i] & kGhost)) key_[i] = cell_key(P.pos[i], P.id[i]);
  }
  // The new grains are sources: a grain held here (its index) or a record that arrived
  // (n_old + its place in arrived_), each with its key.
  order_.clear(), arrived_.clear(), ghost_clumps_.clear();
  auto &down = out_down_, &up = out_up_;
  down.clear(), up.clear();
  std::vector<std::uint8_t> leaving(n_old, 0);
  const int lower = lower_rank(), upper = upper_rank();
  for (std::size_t i = 0; i < n_old; ++i) {
    if (P.flags[i] & kGhost) continue;
    const int to = owner(home(world, i));
    if (to == me) {
      order_.push_back({key_[i], i});
    } else if (to == lower || to == upper) {
      (to == lower ? down : up).push_back(GrainRecord<D>::of(P, i, key_[i], clump_id(world, i)));
      leaving[i] = 1;
    } else {
      throw InstabilityError("grain " + std::to_string(P.id[i]) +
                             " crossed a whole rank's slab (x = " + std::to_string(P.pos[i].x()) +
                             " m) between two neighbour-list builds; likely cause: a runaway "
                             "grain, or slabs too thin");
    }
  }
  // Clumps go with their members; those that stay and those that arrive are the rank's clumps.
  const auto& C = world.clumps;
  clumps_out_down_.clear(), clumps_out_up_.clear();
  std::vector<ClumpRecord<D>> staying;
  for (std::size_t c = 0; c < C.owned(); ++c) {
    const int to = owner(across(C.pos[c]));
    (to == me      ? staying
     : to == lower ? clumps_out_down_
                   : clumps_out_up_)
        .push_back(ClumpRecord<D>::of(C, c));
  }
  // Grains that leave go with every history record they are part of.
  migrated_ += down.size() + up.size();
  collect_history(world, &leaving);
  auto migration = [&](const std::vector<GrainRecord<D>>& grains,
                       const std::vector<ClumpRecord<D>>& clumps, Bytes& b) {
    std::vector<std::uint32_t> ids;
    for (const auto& g : grains) ids.push_back(g.id);
    std::sort(ids.begin(), ids.end());
    std::vector<PairRecord<D>> pairs;
    std::vector<WallRecord<D>> walls;
    std::vector<SparRecord<D>> spars;
    for (const auto& p : pairs_)
      if (contains(ids, p.a) || contains(ids, p.b)) pairs.push_back(p);
    for (const auto& w : walls_)
      if (contains(ids, w.id)) walls.push_back(w);
    for (const auto& r : spars_)
      if (contains(ids, r.id)) spars.push_back(r);
    b.clear();
    put_records(b, grains);
    put_records(b, pairs);
    put_records(b, walls);
    put_records(b, spars);
    put_records(b, clumps);
  };
  migration(down, clumps_out_down_, to_lower_);
  migration(up, clumps_out_up_, to_upper_);
  exchange(to_lower_, to_upper_, from_lower_, from_upper_);
  // The records sent stay here too (any that are still wanted here duplicate rows of the
  // list: the same bits, kept once).
  for (const Bytes* in : {&from_lower_, &from_upper_}) {
    if (in->empty()) continue;
    std::size_t at = 0;
    const std::size_t first = arrived_.size();
    append_records(*in, at, arrived_);
    for (std::size_t k = first; k < arrived_.size(); ++k)
      order_.push_back({arrived_[k].key, n_old + k});
    append_records(*in, at, pairs_);
    append_records(*in, at, walls_);
    append_records(*in, at, spars_);
    append_records(*in, at, staying);
  }
  std::sort(order_.begin(), order_.end());
  std::sort(staying.begin(), staying.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  // Ghosts: this rank's grains within the ghost width of a neighbour's slab, in key order.
  // A ghost member brings its clump's record (the ghost clump names the body it belongs to).
  auto record = [&](const Source& src) {
    return src.second < n_old
               ? GrainRecord<D>::of(P, src.second, src.first, clump_id(world, src.second))
               : arrived_[src.second - n_old];
  };
  down.clear(), up.clear();
  clumps_out_down_.clear(), clumps_out_up_.clear();
  auto send_clump = [&](std::uint32_t id, std::vector<ClumpRecord<D>>& out) {
    if (id == kNoClump || (!out.empty() && out.back().id == id)) return;
    const auto it = std::lower_bound(staying.begin(), staying.end(), id,
                                     [](const auto& r, std::uint32_t v) { return r.id < v; });
    if (it == staying.end() || it->id != id)
      throw std::runtime_error("clump " + std::to_string(id) + " of a grain held here is not");
    out.push_back(*it);
  };
  send_lower_.clear(), send_upper_.clear();  // sources for now, local indices below
  const double reach = in_cuts(ghost_width_);
  // Two ranks in a ring are each other's lower and upper: a grain near both of its slab's
  // ends goes once (the receiver's search finds the image it pairs through).
  const bool one_neighbour = lower >= 0 && lower == upper;
  for (const Source& src : order_) {
    const double x =
        across(src.second < n_old ? P.pos[src.second] : arrived_[src.second - n_old].pos);
    bool sent = false;
    if (lower >= 0 && x < cuts_[static_cast<std::size_t>(me)] + reach) {
      down.push_back(record(src));
      send_clump(down.back().clump, clumps_out_down_);
      send_lower_.push_back(static_cast<std::uint32_t>(src.second));
      sent = one_neighbour;
    }
    if (upper >= 0 && !sent && x >= cuts_[static_cast<std::size_t>(me) + 1] - reach) {
      up.push_back(record(src));
      send_clump(up.back().clump, clumps_out_up_);
      send_upper_.push_back(static_cast<std::uint32_t>(src.second));
    }
  }
  for (auto* out : {&clumps_out_down_, &clumps_out_up_}) {  // each once, by id
    std::sort(out->begin(), out->end(), [](const auto& a, const auto& b) { return a.id < b.id; });
    out->erase(std::unique(out->begin(), out->end(),
                           [](const auto& a, const auto& b) { return a.id == b.id; }),
               out->end());
  }
  to_lower_.clear(), to_upper_.clear();
  put_records(to_lower_, down);
  put_records(to_upper_, up);
  put_records(to_lower_, clumps_out_down_);
  put_records(to_upper_, clumps_out_up_);
  exchange(to_lower_, to_upper_, from_lower_, from_upper_);
  recv_lower_.clear(), recv_upper_.clear();
  for (auto [in, recv] :
       {std::pair{&from_lower_, &recv_lower_}, std::pair{&from_upper_, &recv_upper_}}) {
    if (in->empty()) continue;
    std::size_t at = 0;
    const std::size_t first = arrived_.size();
    append_records(*in, at, arrived_);
    for (std::size_t k = first; k < arrived_.size(); ++k) {
      arrived_[k].flags |= kGhost;
      order_.push_back({arrived_[k].key, n_old + k});
      recv->push_back(static_cast<std::uint32_t>(n_old + k));
    }
    append_records(*in, at, ghost_clumps_);
  }
  // The rank's grains and ghosts, by key.
  std::sort(order_.begin(), order_.end());
  const std::size_t n = order_.size();
  new_index_.assign(n_old + arrived_.size(), 0);
  for (std::size_t k = 0; k < n; ++k) new_index_[order_[k].second] = static_cast<std::uint32_t>(k);
  // Where each grain held until now goes (-1: it left, or a ghost no longer needed).
  std::vector<std::int32_t> old_to_new(n_old, -1);
  for (std::size_t i = 0; i < n_old; ++i)
    if (P.id[i] < index_of_id_.size()) index_of_id_[P.id[i]] = -1;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t src = order_[k].second;
    const std::uint32_t id = src < n_old ? P.id[src] : arrived_[src - n_old].id;
    if (id >= index_of_id_.size()) index_of_id_.resize(id + std::size_t{1}, -1);
    index_of_id_[id] = static_cast<std::int32_t>(k);
  }
  for (std::size_t i = 0; i < n_old; ++i)
    old_to_new[i] = static_cast<std::int32_t>(local_index(P.id[i]));
  if (clumped_) {  // members name their clump by id until the clumps are replaced
    P.clump.resize(n_old, kNoClump), P.body_offset.resize(n_old, Dim<D>::Vec::Zero());
    for (std::size_t i = 0; i < n_old; ++i) P.clump[i] = clump_id(world, i);
  }
  reorder_grains(P, n_old);
  if (clumped_) replace_clumps(P, world.clumps, staying);
  key_.resize(n);
  for (std::size_t k = 0; k < n; ++k) key_[k] = order_[k].first;
  set_slab_starts(world);
  for (auto* list : {&send_lower_, &send_upper_, &recv_lower_, &recv_upper_})
    for (auto& v : *list) v = new_index_[v];
  renumber_rows(world, old_to_new);
  // The scratch goes back: between builds a rank holds what one process would.
  std::vector<PairRecord<D>>().swap(pairs_);
  std::vector<WallRecord<D>>().swap(walls_);
  std::vector<SparRecord<D>>().swap(spars_);
  std::vector<Source>().swap(order_);
  std::vector<GrainRecord<D>>().swap(arrived_);
  std::vector<std::uint32_t>().swap(new_index_);
  for (auto* v : {&clumps_out_down_, &clumps_out_up_, &ghost_clumps_})
    std::vector<ClumpRecord<D>>().swap(*v);
  give_free_heap_back();  // and to the system (base/heap_trim.hpp)
}

// New grain k is order_[k]'s source: built one array at a time (one array of extra memory).
template <int D>
void SlabDomain<D>::reorder_grains(Particles<D>& P, std::size_t n_old) const {
  const std::size_t n = order_.size();
  auto gather = [&](auto& v, auto field) {
    std::remove_reference_t<decltype(v)> out(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t src = order_[k].second;
      out[k] = src < n_old ? v[src] : field(arrived_[src - n_old]);
    }
    v.swap(out);
  };
  gather(P.pos, [](const GrainRecord<D>& g) { return g.pos; });
  gather(P.vel, [](const GrainRecord<D>& g) { return g.vel; });
  gather(P.angvel, [](const GrainRecord<D>& g) { return g.angvel; });
  gather(P.radius, [](const GrainRecord<D>& g) { return g.radius; });
  gather(P.inv_mass, [](const GrainRecord<D>& g) { return g.inv_mass; });
  gather(P.inv_inertia, [](const GrainRecord<D>& g) { return g.inv_inertia; });
  gather(P.material, [](const GrainRecord<D>& g) { return g.material; });
  gather(P.flags, [](const GrainRecord<D>& g) { return g.flags; });
  gather(P.pos_at_build, [](const GrainRecord<D>& g) { return g.pos_at_build; });
  gather(P.id, [](const GrainRecord<D>& g) { return g.id; });
  if (!P.orient.empty()) gather(P.orient, [](const GrainRecord<D>& g) { return g.orient; });
  if (clumped_) {
    gather(P.clump, [](const GrainRecord<D>& g) { return g.clump; });
    gather(P.body_offset, [](const GrainRecord<D>& g) { return g.body_offset; });
  }
  // Forces are set afresh by the next force stage.
  P.force.assign(n, Dim<D>::Vec::Zero());
  P.torque.assign(n, Dim<D>::zero_rot());
}

// The rows of the list in the new numbering: each listed pair with a history of two grains
// still held (not both ghosts) in the row of its first grain, seen from it; then the records
// that arrived.
// Rows sorted by partner, a pair that came twice kept once (the same bits).
template <int D>
void SlabDomain<D>::renumber_rows(World<D>& world, const std::vector<std::int32_t>& old_to_new) {
  const auto& P = world.particles;
  auto& L = world.nlist;
  const std::size_t n = P.size(), n_old = old_to_new.size();
  const bool extras = world.contact_extras;
  const bool have_old = L.start.size() == n_old + 1;
  const bool old_extras = have_old && !L.extra.empty() && L.extra.size() == L.other.size();
  const bool old_wall_extras =
      have_old && !L.wall_extra.empty() && L.wall_extra.size() == L.wall.size();
  const ContactExtra<D> none{};
  auto ghost = [&](std::int64_t i) { return (P.flags[static_cast<std::size_t>(i)] & kGhost) != 0; };
  NeighbourList<D> rows;
  rows.start.assign(n + 1, 0);
  rows.wall_start.assign(n + 1, 0);
  // Pass 1 counts, pass 2 fills: (a, b, spring, extra as seen from a's row).
  auto each_pair = [&](auto&& put) {
    if (have_old)
      for (std::size_t i = 0; i < n_old; ++i)
        for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
          const std::int64_t a = old_to_new[i], b = old_to_new[L.other[k]];
          if (a < 0 || b < 0 || (ghost(a) && ghost(b))) continue;
          const ContactExtra<D>& e = old_extras ? L.extra[k] : none;
          // Only pairs with a history: the build gives the others the unloaded start.
          if (zero_bits(L.spring[k]) && e.bonded == 0 && zero_bits(e.roll) && zero_bits(e.twist))
            continue;
          put(a, b, L.spring[k], e);
        }
    for (const auto& p : pairs_) {
      const std::int64_t a = local_index(p.a), b = local_index(p.b);
      if (a < 0 || b < 0 || (ghost(a) && ghost(b))) continue;
      put(a, b, p.spring, p.extra);
    }
  };
  each_pair([&](std::int64_t a, std::int64_t b, const auto&, const auto&) {
    ++rows.start[static_cast<std::size_t>(std::min(a, b)) + 1];
  });
  for (std::size_t i = 0; i < n; ++i) rows.start[i + 1] += rows.start[i];
  const std::size_t total = rows.start[n];
  rows.other.resize(total);
  rows.spring.resize(total);
  rows.extra.resize(extras ? total : 0);
  std::vector<std::uint32_t> fill(rows.start.begin(), rows.start.end() - 1);
  each_pair([&](std::int64_t a, std::int64_t b, const TangentSpring<D>& s, ContactExtra<D> e) {
    const auto row = static_cast<std::size_t>(std::min(a, b));
    const std::uint32_t slot = fill[row]++;
    rows.other[slot] = static_cast<std::uint32_t>(std::max(a, b));
    rows.spring[slot] = a < b ? s : spring_from_other_body<D>(s);
    if (a > b) e.roll = -e.roll;  // seen from the other grain (as in renumbering)
    if (extras) rows.extra[slot] = e;
  });
  // Rows sorted by partner, then duplicates dropped.
  std::size_t kept = 0;
  std::uint32_t row_begin = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = row_begin, e = rows.start[i + 1];
    sort_row_by_partner(rows.other.data(), rows.spring.data(), extras ? rows.extra.data() : nullptr,
                        b, e);
    const std::size_t first = kept;
    for (std::uint32_t x = b; x < e; ++x) {
      if (kept > first && rows.other[kept - 1] == rows.other[x]) continue;
      rows.other[kept] = rows.other[x], rows.spring[kept] = rows.spring[x];
      if (extras) rows.extra[kept] = rows.extra[x];
      ++kept;
    }
    row_begin = e;
    rows.start[i + 1] = static_cast<std::uint32_t>(kept);
  }
  rows.other.resize(kept), rows.spring.resize(kept);
  if (extras) rows.extra.resize(kept);
  // Grain-wall rows: the rank's own grains only (ghosts have no walls).
  std::vector<std::tuple<std::uint32_t, std::uint32_t, TangentSpring<D>, ContactExtra<D>>> walls;
  if (have_old && L.wall_start.size() == n_old + 1)
    for (std::size_t i = 0; i < n_old; ++i)
      for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k)
        if (old_to_new[i] >= 0 && !ghost(old_to_new[i]))
          walls.emplace_back(static_cast<std::uint32_t>(old_to_new[i]), L.wall[k], L.wall_spring[k],
                             old_wall_extras ? L.wall_extra[k] : none);
  for (const auto& w : walls_) {
    const std::int64_t i = local_index(w.id);
    if (i >= 0 && !ghost(i))
      walls.emplace_back(static_cast<std::uint32_t>(i), w.wall, w.spring, w.extra);
  }
  std::sort(walls.begin(), walls.end(), [](const auto& x, const auto& y) {
    return std::get<0>(x) != std::get<0>(y) ? std::get<0>(x) < std::get<0>(y)
                                            : std::get<1>(x) < std::get<1>(y);
  });
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const auto& [row, wall, spring, extra] = walls[k];
    if (k > 0 && std::get<0>(walls[k - 1]) == row && std::get<1>(walls[k - 1]) == wall) continue;
    ++rows.wall_start[row + 1];
    rows.wall.push_back(wall);
    rows.wall_spring.push_back(spring);
    if (extras) rows.wall_extra.push_back(extra);
  }
  for (std::size_t i = 0; i < n; ++i) rows.wall_start[i + 1] += rows.wall_start[i];
  // Grain-spar rows the same way: the rank's own grains, by element.
  if (!world.spars.empty()) {
    std::vector<std::tuple<std::uint32_t, std::uint32_t, TangentSpring<D>>> spars;
    if (have_old && L.spar_start.size() == n_old + 1)
      for (std::size_t i = 0; i < n_old; ++i)
        for (std::uint32_t k = L.spar_start[i]; k < L.spar_start[i + 1]; ++k)
          if (old_to_new[i] >= 0 && !ghost(old_to_new[i]) && !zero_bits(L.spar_spring[k]))
            spars.emplace_back(static_cast<std::uint32_t>(old_to_new[i]), L.spar[k],
                               L.spar_spring[k]);
    for (const auto& r : spars_) {
      const std::int64_t i = local_index(r.id);
      if (i >= 0 && !ghost(i))
        spars.emplace_back(static_cast<std::uint32_t>(i), r.element, r.spring);
    }
    std::sort(spars.begin(), spars.end(), [](const auto& x, const auto& y) {
      return std::tie(std::get<0>(x), std::get<1>(x)) < std::tie(std::get<0>(y), std::get<1>(y));
    });
    rows.spar_start.assign(n + 1, 0);
    for (std::size_t k = 0; k < spars.size(); ++k) {
      const auto& [row, element, spring] = spars[k];
      if (k > 0 && std::get<0>(spars[k - 1]) == row && std::get<1>(spars[k - 1]) == element)
        continue;
      ++rows.spar_start[row + 1];
      rows.spar.push_back(element);
      rows.spar_spring.push_back(spring);
    }
    for (std::size_t i = 0; i < n; ++i) rows.spar_start[i + 1] += rows.spar_start[i];
  }
  L.swap_rows(rows);
}

// (the class's other members are instantiated in slab_domain.cpp)
template void SlabDomain<2>::before_build(World<2>&);
template void SlabDomain<3>::before_build(World<3>&);
template void SlabDomain<2>::reorder_grains(Particles<2>&, std::size_t) const;
template void SlabDomain<3>::reorder_grains(Particles<3>&, std::size_t) const;
template void SlabDomain<2>::renumber_rows(World<2>&, const std::vector<std::int32_t>&);
template void SlabDomain<3>::renumber_rows(World<3>&, const std::vector<std::int32_t>&);

}  // namespace geodem
