#include "domain/slab_domain.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "base/cpu_time.hpp"
#include "base/error.hpp"
#include "broadphase/list_history.hpp"
#include "broadphase/periodic_search.hpp"
#include "world/world_editing.hpp"

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

}  // namespace

template <int D>
std::shared_ptr<SlabDomain<D>> SlabDomain<D>::distribute(World<D>& world,
                                                         std::shared_ptr<DomainComm> comm,
                                                         const DomainCheckpoint<D>* resumed) {
  auto d = std::shared_ptr<SlabDomain>(new SlabDomain(std::move(comm)));
  auto& P = world.particles;
  d->periodic_ = world.cell.periodic;
  d->comm_->ring = d->periodic_;
  // (a resumed run keeps its positions: its grains are brought into the cell at its builds)
  if (d->periodic_ && !resumed) wrap_into_cell(world);
  if (d->periodic_) d->take_cell(world);
  const std::size_t n = P.size();
  const int ranks = d->comm_->size(), me = d->comm_->rank();
  double rmax = 0.0;
  ExactSum radii;  // the same skin on every rank, whatever order the grains are in
  for (std::size_t i = 0; i < n; ++i) rmax = std::max(rmax, P.radius[i]), radii.add(P.radius[i]);
  d->skin_ = n > 0 ? world.skin_factor * radii.value() / static_cast<double>(n) : 0.0;
  d->clumped_ = !P.clump.empty();
  if (world.clumps.size() > 0) {
    double offset = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      if (P.clump[i] != kNoClump) offset = std::max(offset, P.body_offset[i].norm());
    d->extent_ = offset + 0.5 * d->skin_;
  }
  d->ghost_width_ = 2.0 * rmax + d->skin_ + d->extent_;
  if (resumed)
    d->skin_ = resumed->skin, d->ghost_width_ = resumed->ghost_width, d->extent_ = resumed->extent;
  // Cuts at equal grain counts along x (a periodic cell: along its fractional coordinate).
  std::vector<double> xs(n);
  for (std::size_t i = 0; i < n; ++i) xs[i] = d->across(P.pos[i]);
  std::sort(xs.begin(), xs.end());
  const double inf = std::numeric_limits<double>::infinity();
  d->cuts_.assign(static_cast<std::size_t>(ranks) + 1, d->periodic_ ? 0.0 : -inf);
  d->cuts_.back() = d->periodic_ ? 1.0 : inf;
  for (int q = 1; q < ranks; ++q)
    d->cuts_[static_cast<std::size_t>(q)] =
        n > 0 ? xs[static_cast<std::size_t>(q) * n / static_cast<std::size_t>(ranks)] : 0.0;
  // A grain moves less than the skin between builds, and ghosts come from the next slab only:
  // the inner slabs must be at least a ghost width across.
  d->refuse_thin_slabs(std::to_string(ranks) + " ranks cut the grains into slabs");
  // The keys' grid: the grains' bounding box now, cells a ghost width across (grains that
  // leave the box later take the edge cells until the keys are retaken, with a new grid).
  d->sort_every_ = world.sort_interval;
  if (resumed) {
    if (resumed->keys.size() != n)
      throw std::runtime_error("the checkpoint's keys do not match its grains");
    d->sort_every_ = static_cast<int>(resumed->sort_every);
    d->grid_lo_ = resumed->grid_lo;
    d->grid_dims_ = resumed->grid_dims;
    d->key_block_ = resumed->key_block;
  } else if (n > 0) {
    typename Dim<D>::Vec lo = P.pos[0], hi = P.pos[0];
    for (std::size_t i = 0; i < n; ++i) lo = lo.cwiseMin(P.pos[i]), hi = hi.cwiseMax(P.pos[i]);
    d->set_grid(lo, hi, n, world.one_slab);
  }
  world.one_slab = d->key_block_ == 0;
  if (resumed) {
    d->pairs_ = resumed->pairs, d->walls_ = resumed->walls, d->spars_ = resumed->spars;
  } else {
    d->collect_history(world, nullptr);
  }
  std::vector<std::uint32_t> mine;
  std::vector<std::uint64_t> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = resumed ? resumed->keys[i] : d->cell_key(P.pos[i], P.id[i]);
    if (d->owner(d->home(world, i)) == me) mine.push_back(static_cast<std::uint32_t>(i));
  }
  std::sort(mine.begin(), mine.end(), [&](auto a, auto b) { return keys[a] < keys[b]; });
  // The clumps whose centre is in the slab, with all their members.
  std::vector<ClumpRecord<D>> clumps;
  for (std::size_t c = 0; c < world.clumps.size(); ++c)
    if (d->owner(d->across(world.clumps.pos[c])) == me)
      clumps.push_back(ClumpRecord<D>::of(world.clumps, c));
  if (d->clumped_)
    for (std::size_t i = 0; i < n; ++i) P.clump[i] = d->clump_id(world, i);
  P.permute(mine);
  if (d->clumped_) d->replace_clumps(P, world.clumps, clumps);
  d->key_.resize(mine.size());
  for (std::size_t k = 0; k < mine.size(); ++k) d->key_[k] = keys[mine[k]];
  NeighbourList<D> none;
  world.nlist.swap_rows(none);
  d->set_slab_starts(world);
  world.sort_interval = 0;  // the domain orders the grains (by key)
  world.rebuild_needed = true;
  // The rank's work (its thread's CPU time) is counted from here.
  d->work_at_rebalance_ = thread_cpu_seconds();
  // World-wide counts that ranks add up start on rank 0 alone.
  if (me != 0) world.broken_bonds = 0;
  world.domain = d;
  if (resumed) d->rebuild_as_saved(world);
  return d;
}

template <int D>
double SlabDomain<D>::home(const World<D>& world, std::size_t i) const {
  const auto& P = world.particles;
  return across(clumped_ && P.clump[i] != kNoClump ? world.clumps.pos[P.clump[i]] : P.pos[i]);
}

template <int D>
void SlabDomain<D>::take_cell(const World<D>& world) {
  s_row_ = world.cell.h.inverse().row(0).transpose();
  width_ = 1.0 / s_row_.norm();
}

template <int D>
int SlabDomain<D>::lower_rank() const {
  const int me = comm_->rank(), ranks = comm_->size();
  return me > 0 ? me - 1 : periodic_ && ranks > 1 ? ranks - 1 : -1;
}

template <int D>
int SlabDomain<D>::upper_rank() const {
  const int me = comm_->rank(), ranks = comm_->size();
  return me + 1 < ranks ? me + 1 : periodic_ && ranks > 1 ? 0 : -1;
}

template <int D>
std::uint32_t SlabDomain<D>::clump_id(const World<D>& world, std::size_t i) const {
  const auto& P = world.particles;
  return clumped_ && P.clump[i] != kNoClump ? world.clumps.id[P.clump[i]] : kNoClump;
}

template <int D>
int SlabDomain<D>::owner(double x) const {
  const auto it = std::upper_bound(cuts_.begin() + 1, cuts_.end() - 1, x);
  return static_cast<int>(it - (cuts_.begin() + 1));
}

template <int D>
std::uint64_t SlabDomain<D>::cell_key(const typename Dim<D>::Vec& x, std::uint32_t id) const {
  if (sort_every_ <= 0) return id;
  std::uint64_t cell = 0;
  // x slowest: a block of consecutive cells (a force slab, set_slab_starts) is then a slice
  // across x, like the ranks' slabs, and only contacts across its two faces cross to another
  // slab. (With x fastest, as the neighbour search's cells, a block was a strip of one layer
  // of cells, every contact between layers crossed, and a rank on one thread ran 24 % slower
  // than with one slab on a 200,000-sphere bed.)
  for (int k = 0; k < D; ++k) {
    const auto dims = grid_dims_[static_cast<std::size_t>(k)];
    const double c = std::floor((x[k] - grid_lo_[k]) / ghost_width_);
    const auto ck = c <= 0.0 ? 0 : std::min(static_cast<std::uint64_t>(c), dims - 1);
    cell = cell * dims + ck;
  }
  return (cell << 32) | id;
}

template <int D>
void SlabDomain<D>::set_grid(const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                             std::uint64_t grains, bool one_slab) {
  grid_lo_ = lo;
  std::uint64_t cells = 1;
  for (int k = 0; k < D; ++k) {
    auto& dims = grid_dims_[static_cast<std::size_t>(k)];
    dims = static_cast<std::uint64_t>(std::floor((hi[k] - lo[k]) / ghost_width_)) + 1;
    cells *= dims;
  }
  // Force slabs of blocks of keys holding about max(2,048, N / 512) grains (the same blocks on
  // every rank: a slab's grains are then the same whatever the ranks hold).
  if (one_slab || grains == 0) {
    key_block_ = 0;
    return;
  }
  const std::uint64_t target = std::max<std::uint64_t>(2048, grains / 512);
  key_block_ = sort_every_ > 0 ? std::max<std::uint64_t>(1, target * cells / grains) : target;
}

template <int D>
void SlabDomain<D>::set_slab_starts(World<D>& world) const {
  auto& starts = world.slab_starts;
  starts.clear();
  if (key_block_ == 0) return;
  auto block = [&](std::uint64_t key) {
    return (sort_every_ > 0 ? key >> 32 : key & 0xffffffffu) / key_block_;
  };
  starts.push_back(0);
  for (std::size_t i = 1; i < key_.size(); ++i)
    if (block(key_[i]) != block(key_[i - 1])) starts.push_back(static_cast<std::uint32_t>(i));
  starts.push_back(static_cast<std::uint32_t>(key_.size()));
}

template <int D>
std::int64_t SlabDomain<D>::local_index(std::uint32_t id) const {
  return id < index_of_id_.size() ? index_of_id_[id] : -1;
}

template <int D>
std::size_t SlabDomain<D>::owned(const World<D>& world) const {
  const auto& f = world.particles.flags;
  return static_cast<std::size_t>(
      std::count_if(f.begin(), f.end(), [](std::uint8_t v) { return !(v & kGhost); }));
}

namespace {
// Adds the wall time of a scope to a total, and with `cpu` the calling thread's CPU time to
// another (a system call each way: taken only when the rebalance measures time).
class Timed {
 public:
  Timed(double& wall, double* cpu)
      : wall_(wall), cpu_(cpu), cpu0_(cpu ? thread_cpu_seconds() : 0.0) {}
  ~Timed() {
    wall_ += std::chrono::duration<double>(Clock::now() - t0_).count();
    if (cpu_) *cpu_ += thread_cpu_seconds() - cpu0_;
  }
  Timed(const Timed&) = delete;
  Timed& operator=(const Timed&) = delete;

 private:
  using Clock = std::chrono::steady_clock;
  double& wall_;
  double* cpu_;
  double cpu0_;
  Clock::time_point t0_ = Clock::now();
};
}  // namespace

template <int D>
bool SlabDomain<D>::any_rank(bool here) {
  Timed t(comm_seconds_, rebalance_on_time ? &comm_cpu_seconds_ : nullptr);
  return comm_->max(here ? 1.0 : 0.0) > 0.5;
}

template <int D>
double SlabDomain<D>::min_over_ranks(double here) {
  Timed t(comm_seconds_, rebalance_on_time ? &comm_cpu_seconds_ : nullptr);
  return comm_->min(here);
}

template <int D>
std::string SlabDomain<D>::first_text(const std::string& here) {
  Timed t(comm_seconds_, rebalance_on_time ? &comm_cpu_seconds_ : nullptr);
  // Each rank's text with its length in front, in rank order.
  const std::uint64_t n = here.size();
  Bytes framed(sizeof n + here.size());
  std::memcpy(framed.data(), &n, sizeof n);
  if (n > 0) std::memcpy(framed.data() + sizeof n, here.data(), here.size());
  const Bytes all = comm_->all_gather(framed);
  std::size_t at = 0;
  while (at + sizeof n <= all.size()) {
    std::uint64_t len = 0;
    std::memcpy(&len, all.data() + at, sizeof len);
    at += sizeof len;
    if (len > 0) return std::string(reinterpret_cast<const char*>(all.data() + at), len);
    at += len;
  }
  return {};
}

template <int D>
void SlabDomain<D>::exchange(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower,
                             Bytes& from_upper) {
  Timed t(comm_seconds_, rebalance_on_time ? &comm_cpu_seconds_ : nullptr);
  comm_->exchange(to_lower, to_upper, from_lower, from_upper);
}

template <int D>
void SlabDomain<D>::sum(std::vector<ExactSum>& sums) {
  Timed t(comm_seconds_, rebalance_on_time ? &comm_cpu_seconds_ : nullptr);
  comm_->sum(sums);
}

template <int D>
void SlabDomain<D>::collect_history(const World<D>& world, const std::vector<std::uint8_t>* only) {
  const auto& P = world.particles;
  const auto& L = world.nlist;
  const std::size_t n = P.size();
  if (L.start.size() != n + 1) return;
  const bool extras = !L.extra.empty() && L.extra.size() == L.other.size();
  const bool wall_extras = !L.wall_extra.empty() && L.wall_extra.size() == L.wall.size();
  const ContactExtra<D> none{};
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t k = L.start[i]; k < L.start[i + 1]; ++k) {
      if (only && !(*only)[i] && !(*only)[L.other[k]]) continue;
      const ContactExtra<D>& e = extras ? L.extra[k] : none;
      if (loaded<D>(L.spring[k], e))
        pairs_.push_back(pair_record<D>(P.id[i], P.id[L.other[k]], L.spring[k], e));
    }
    if (only && !(*only)[i]) continue;
    if (L.wall_start.size() == n + 1)
      for (std::uint32_t k = L.wall_start[i]; k < L.wall_start[i + 1]; ++k) {
        const ContactExtra<D>& e = wall_extras ? L.wall_extra[k] : none;
        if (loaded<D>(L.wall_spring[k], e))
          walls_.push_back({P.id[i], L.wall[k], L.wall_spring[k], e});
      }
    if (L.spar_start.size() == n + 1)
      for (std::uint32_t k = L.spar_start[i]; k < L.spar_start[i + 1]; ++k)
        if (!zero_bits(L.spar_spring[k])) spars_.push_back({P.id[i], L.spar[k], L.spar_spring[k]});
  }
}

template <int D>
void SlabDomain<D>::grains_kept(World<D>& world, const std::vector<std::uint32_t>& keep) {
  std::vector<std::uint64_t> kept(keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) kept[k] = key_[keep[k]];
  key_.swap(kept);
  set_slab_starts(world);
  std::fill(index_of_id_.begin(), index_of_id_.end(), -1);
  const auto& P = world.particles;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.id[i] < index_of_id_.size()) index_of_id_[P.id[i]] = static_cast<std::int32_t>(i);
  // Removal keeps the clumps' order: the ghost clumps that are left are still the last.
  auto& C = world.clumps;
  if (C.size() > 0) {
    std::vector<std::uint8_t> ghost(C.size(), 0);
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.clump[i] != kNoClump && (P.flags[i] & kGhost)) ghost[P.clump[i]] = 1;
    C.ghosts = static_cast<std::size_t>(std::count(ghost.begin(), ghost.end(), 1));
  }
  // (the ghost update's lists are made anew by the build before the next step's motion)
  send_lower_.clear(), send_upper_.clear(), recv_lower_.clear(), recv_upper_.clear();
}

template <int D>
void SlabDomain<D>::grains_added(World<D>& world, std::size_t first_grain,
                                 std::size_t first_clump) {
  auto& P = world.particles;
  auto& C = world.clumps;
  const int me = comm_->rank();
  clumped_ = !P.clump.empty();
  // The new grains this rank owns, the others dropped (every rank added them all).
  std::vector<std::uint32_t> keep(first_grain);
  for (std::size_t i = 0; i < first_grain; ++i) keep[i] = static_cast<std::uint32_t>(i);
  double rmax = 0.0, offset = 0.0;
  for (std::size_t i = first_grain; i < P.size(); ++i) {
    rmax = std::max(rmax, P.radius[i]);
    if (clumped_ && P.clump[i] != kNoClump) offset = std::max(offset, P.body_offset[i].norm());
    if (owner(home(world, i)) == me) keep.push_back(static_cast<std::uint32_t>(i));
  }
  // Clumps: the rank's own, its new ones, then the ghost clumps (still last).
  const std::size_t owned_before = first_clump - C.ghosts;
  std::vector<std::uint32_t> order, index(C.size(), kNoClump);
  for (std::size_t c = 0; c < owned_before; ++c) order.push_back(static_cast<std::uint32_t>(c));
  for (std::size_t c = first_clump; c < C.size(); ++c)
    if (owner(across(C.pos[c])) == me) order.push_back(static_cast<std::uint32_t>(c));
  for (std::size_t c = owned_before; c < first_clump; ++c)
    order.push_back(static_cast<std::uint32_t>(c));
  for (std::size_t k = 0; k < order.size(); ++k) index[order[k]] = static_cast<std::uint32_t>(k);
  P.permute(keep);
  C.permute(order);
  if (clumped_)
    for (auto& c : P.clump)
      if (c != kNoClump) c = index[c];
  for (std::size_t i = first_grain; i < P.size(); ++i) {
    key_.push_back(cell_key(P.pos[i], P.id[i]));
    if (P.id[i] >= index_of_id_.size()) index_of_id_.resize(P.id[i] + std::size_t{1}, -1);
    index_of_id_[P.id[i]] = static_cast<std::int32_t>(i);
  }
  set_slab_starts(world);  // the next build puts the new grains in key order
  // Empty list rows for the kept new grains, so that the next build keeps the others' history.
  add_list_rows_for_new_grains(world, first_grain);
  // The reach of the new grains (every rank saw them all: the same on every rank).
  extent_ = std::max(extent_, offset > 0.0 ? offset + 0.5 * skin_ : 0.0);
  ghost_width_ = std::max(ghost_width_, 2.0 * rmax + skin_ + extent_);
  refuse_thin_slabs("the grains added make the ghost width " + std::to_string(ghost_width_) + " m");
  world.rebuild_needed = true;
}

template <int D>
void SlabDomain<D>::refuse_thin_slabs(const std::string& cause) const {
  // (in a periodic cell every slab has two neighbours, the first and last across the faces;
  // its width is taken in metres across the cell as it is now)
  const std::size_t first = periodic_ && comm_->size() > 1 ? 0 : 1;
  const std::size_t last = periodic_ && comm_->size() > 1 ? cuts_.size() - 1 : cuts_.size() - 2;
  const double metres = periodic_ ? width_ : 1.0;
  for (std::size_t q = first; q < last; ++q)
    if ((cuts_[q + 1] - cuts_[q]) * metres < min_slab())
      throw InputError("", 0, "",
                       cause + ": a slab of " + std::to_string((cuts_[q + 1] - cuts_[q]) * metres) +
                           " m is too thin, less than " + std::to_string(min_slab()) +
                           " m (the ghost width, 2 x largest radius + skin, and twice a "
                           "clump's reach); use fewer ranks (docs/parallel.md)");
}

template <int D>
void SlabDomain<D>::after_integration(World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  using Orient = typename Dim<D>::Orient;
  auto& P = world.particles;
  // Per ghost: position, velocity, angular velocity, and the orientation only if tracked.
  const bool track = !P.orient.empty();
  const std::size_t size = 2 * sizeof(Vec) + sizeof(Rot) + (track ? sizeof(Orient) : 0);
  auto pack = [&](const std::vector<std::uint32_t>& idx, Bytes& out) {
    out.resize(idx.size() * size);
    std::byte* at = out.data();
    auto put = [&at](const auto& v) {
      std::memcpy(at, static_cast<const void*>(&v), sizeof v);
      at += sizeof v;
    };
    for (const std::uint32_t i : idx) {
      put(P.pos[i]), put(P.vel[i]), put(P.angvel[i]);
      if (track) put(P.orient[i]);
    }
  };
  auto unpack = [&](const Bytes& in, const std::vector<std::uint32_t>& idx) {
    if (in.size() != idx.size() * size)
      throw std::runtime_error("ghost update of " + std::to_string(in.size()) + " bytes for " +
                               std::to_string(idx.size()) + " ghosts");
    const std::byte* at = in.data();
    auto take = [&at](auto& v) {
      std::memcpy(static_cast<void*>(&v), at, sizeof v);
      at += sizeof v;
    };
    for (const std::uint32_t i : idx) {
      take(P.pos[i]), take(P.vel[i]), take(P.angvel[i]);
      if (track) take(P.orient[i]);
    }
  };
  pack(send_lower_, halo_out_lower_);
  pack(send_upper_, halo_out_upper_);
  exchange(halo_out_lower_, halo_out_upper_, halo_in_lower_, halo_in_upper_);
  unpack(halo_in_lower_, recv_lower_);
  unpack(halo_in_upper_, recv_upper_);
  halo_bytes_ = halo_out_lower_.size() + halo_out_upper_.size();
}

template class SlabDomain<2>;
template class SlabDomain<3>;

}  // namespace geodem
