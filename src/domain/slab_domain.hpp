// Spatial decomposition of a world over ranks in slabs along x (docs/parallel.md).
//
// In a periodic cell the slabs are cut along the cell's first fractional coordinate
// (s = row 0 of h^-1 times x, in [0, 1)) and close in a ring: the first and last ranks are
// neighbours across the cell's faces. Each owner brings its grains back into the cell before
// a build; a ghost keeps its owner's position and the neighbour search finds the image it is
// seen through, as for any pair across the faces.
//
// Each rank owns the grains whose centre lies in its slab [cut[r], cut[r+1]) and holds ghost
// copies of the grains of the neighbouring slabs within the ghost width (2 r_max + skin) of
// its boundaries: every contact of an owned grain is then in the rank's list. A contact
// between an owned grain and a ghost is computed on both ranks, from the same bits, so that
// no force is sent back; ghosts pair with owned grains only and have no walls. On every rank
// the grains are ordered by key, and the force stage's slabs (base/parallel.hpp) begin where
// the keys enter a new block of the domain's key space, so each grain sums its contacts in an
// order its partners' keys alone decide: the same bits for any number of ranks, and for any
// number of threads in each. A key is the grain's cell in a grid the whole domain shares
// (taken anew over all its grains at each retake), taken by its owner every sort_interval
// list builds (as one process renumbers grains in cell
// order), then its id; with sort_interval = 0 it is the id alone. A world distributed with
// one_slab set keeps one slab a rank (its bits are those of one process with one slab).
//
// At each neighbour-list build (all ranks together) grains that left their slab move to the
// neighbour with the history of their contacts, the ghosts are renewed, and the list's old
// rows are rewritten from history records keyed by grain ids. After each step the ghosts
// take their owners' new state.
#pragma once

#include <array>
#include <limits>
#include <memory>
#include <vector>

#include "domain/domain_comm.hpp"
#include "domain/grain_records.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
class SlabDomain final : public DomainHooks<D> {
 public:
  // Splits a world that every rank built identically (all grains, walls, materials): the cuts
  // put equal grain counts in the slabs; each rank keeps its own grains and the contact
  // history they had, and the world gets this domain as its hooks. A clump belongs to the rank
  // of its centre, with all its members; every rank holds the whole spar chains (their loads
  // are summed over ranks). Throws InputError when a slab would be thinner than the ghost
  // width.
  //
  // With `resumed`: the world was loaded from a checkpoint of a decomposed run (checkpoint()
  // below), on any number of ranks. The grains keep their keys, and the list is rebuilt as the
  // run's last build made it (from the positions then, the walls where they were, the same
  // build count): the run goes on with the bits it would have had uninterrupted.
  static std::shared_ptr<SlabDomain> distribute(World<D>& world, std::shared_ptr<DomainComm> comm,
                                                const DomainCheckpoint<D>* resumed = nullptr);
  // A checkpoint (all ranks call it): returns on rank 0 the whole domain's grains in key order,
  // without ghosts, with its clumps in id order in `clumps`, and fills `saved` with their
  // keys, the grid and every contact's history (each once); other ranks get nothing.
  Particles<D> checkpoint(const World<D>& world, DomainCheckpoint<D>& saved, Clumps<D>& clumps);

  bool any_rank(bool here) override;
  double min_over_ranks(double here) override;
  void sum(std::vector<ExactSum>& sums) override;
  std::string first_text(const std::string& here) override;
  int rank() const override { return comm_->rank(); }
  int ranks() const override { return comm_->size(); }
  double skin() const override { return skin_; }
  void before_build(World<D>& world) override;
  void grains_kept(World<D>& world, const std::vector<std::uint32_t>& keep) override;
  // Grains (and clumps) were appended to the world by every rank alike (a stage's cloud,
  // placed clear of the whole domain's grains): each rank keeps those whose centre (a
  // member: its clump's) lies in its slab. The ghost width grows if the new grains need it;
  // throws InputError when a slab is then too thin. All ranks call it.
  void grains_added(World<D>& world, std::size_t first_grain, std::size_t first_clump);
  void after_integration(World<D>& world) override;
  std::uint64_t region_moves() const override { return cut_moves_; }

  // A copy of this domain's state, for a copy of its world (a lab test's prepared sample,
  // which each test starts from): the copy goes on as this domain would from here.
  // (Its work is counted afresh from its first window: the copy may step on another thread.)
  std::shared_ptr<SlabDomain> copy() const {
    auto d = std::shared_ptr<SlabDomain>(new SlabDomain(*this));
    d->work_at_rebalance_ = std::numeric_limits<double>::quiet_NaN();
    d->uneven_windows_ = 0;
    return d;
  }
  DomainComm& comm() { return *comm_; }
  // Every this many list builds the ranks weigh their grains' work; when the busiest rank is
  // over rebalance_tolerance above an even share in rebalance_persistence such windows in a
  // row, the cuts move rebalance_damping of the way to equal work (domain/balanced_cuts.hpp).
  // The work is modelled from each grain's contacts (the same on every run: the cuts are
  // reproducible), or with rebalance_on_time measured as each rank's thread CPU time less
  // that in messages (it sees a slower machine, but also its noise: on a 2-core machine it
  // moved cuts off a balanced bed; then a persistence of 2 and a damping of 0.5 are advised).
  // 0: the cuts never move. Results do not depend on it: any cuts give the same bits
  // (docs/parallel.md, "Rebalancing").
  int rebalance_every = 10;
  double rebalance_tolerance = 0.05;
  int rebalance_persistence = 1;
  double rebalance_damping = 1.0;
  bool rebalance_on_time = false;
  const std::vector<double>& cuts() const { return cuts_; }
  // The busiest rank's work over an even share at the last window (1: balanced; before it
  // moved the cuts), 0 before the first.
  double work_imbalance() const { return work_imbalance_; }
  double ghost_width() const { return ghost_width_; }
  // The thinnest an inner slab may be: the ghost width and the clumps' reach.
  double thinnest_slab() const { return min_slab(); }
  // Grains this rank owns (the world's other grains are ghosts).
  std::size_t owned(const World<D>& world) const;
  // Bytes sent to the neighbours by the last step's ghost update.
  std::size_t halo_bytes() const { return halo_bytes_; }
  // Grains this rank sent to a neighbour to own since the distribution.
  std::uint64_t migrated() const { return migrated_; }

 private:
  explicit SlabDomain(std::shared_ptr<DomainComm> comm) : comm_(std::move(comm)) {}
  int owner(double x) const;
  void rebalance(const World<D>& world);
  // Each local grain's work for the rebalance (ghosts: 0 or unused), modelled or measured.
  std::vector<double> modelled_work(const World<D>& world) const;
  std::vector<double> measured_work(const World<D>& world);
  // comm_->exchange, its time (waiting included) counted in comm_seconds_ (wall) and
  // comm_cpu_seconds_ (the thread's CPU, taken with rebalance_on_time only).
  void exchange(const Bytes& to_lower, const Bytes& to_upper, Bytes& from_lower, Bytes& from_upper);
  std::uint64_t cell_key(const typename Dim<D>::Vec& x, std::uint32_t id) const;
  // The keys' grid over the box [lo, hi] of the domain's `grains`, and the block of keys of a
  // force slab (0 with `one_slab`).
  void set_grid(const typename Dim<D>::Vec& lo, const typename Dim<D>::Vec& hi,
                std::uint64_t grains, bool one_slab);
  // The force slabs' starts (World::slab_starts) from the grains' keys: a slab for each run of
  // keys in one block.
  void set_slab_starts(World<D>& world) const;
  // The ghost width grown to the grains' present reach (every rank at a build).
  void follow_grain_growth(const World<D>& world);
  std::int64_t local_index(std::uint32_t id) const;
  // A point's coordinate across the slabs: x, or in a periodic cell its first fractional
  // coordinate (from the cell at the last build).
  double across(const typename Dim<D>::Vec& x) const { return periodic_ ? s_row_.dot(x) : x.x(); }
  // Where a grain belongs: across() of its centre, or of a member's clump's centre.
  double home(const World<D>& world, std::size_t i) const;
  // The cell's shape at a build (a periodic cell deforms): s_row_ and width_.
  void take_cell(const World<D>& world);
  // A length in the units of across(): metres, or fractions of the cell's width across x.
  double in_cuts(double metres) const { return periodic_ ? metres / width_ : metres; }
  // The neighbours a grain may move to or be a ghost on (-1: none): with a ring, rank 0's
  // lower is the last rank.
  int lower_rank() const;
  int upper_rank() const;
  std::uint32_t clump_id(const World<D>& world, std::size_t i) const;
  // The clumps anew (slab_clumps.cpp): `owned` then the ghost clumps that arrived, each by id;
  // the grains' clump ids become indices.
  void replace_clumps(Particles<D>& P, Clumps<D>& C, std::vector<ClumpRecord<D>>& owned);
  // History records (keyed by ids) of the listed contacts with a history: all of them, or
  // those of the grains marked in `only`.
  void collect_history(const World<D>& world, const std::vector<std::uint8_t>* only);
  void reorder_grains(Particles<D>& P, std::size_t n_old) const;
  void rebuild_as_saved(World<D>& world);
  void renumber_rows(World<D>& world, const std::vector<std::int32_t>& old_to_new);

  std::shared_ptr<DomainComm> comm_;
  std::vector<double> cuts_;  // size + 1 values, -inf and +inf at the ends (periodic: 0 and 1)
  // A periodic cell: row 0 of h^-1 and the cell's width across x at the last build.
  bool periodic_ = false;
  typename Dim<D>::Vec s_row_ = Dim<D>::Vec::UnitX();
  double width_ = 1.0;
  // The grid of the keys (the whole domain's bounding box at distribution, cells a ghost width
  // across) and how often keys are retaken (list builds; 0: never, keys are ids).
  typename Dim<D>::Vec grid_lo_ = Dim<D>::Vec::Zero();
  std::array<std::uint64_t, 3> grid_dims_{1, 1, 1};
  int sort_every_ = 0;
  // Keys per block of a force slab: cells of the grid (sort_every_ > 0) or ids; 0: one slab.
  std::uint64_t key_block_ = 0;
  std::vector<std::uint64_t> key_;         // per local grain
  std::vector<std::int32_t> index_of_id_;  // local index of each grain id held, else -1
  // A build's scratch (given back at its end, but for the small buffers): the new grains'
  // sources (key, old index or n_old + place in arrived_), the records that arrived, the
  // grains leaving or sent as ghosts, where each source goes, and the messages.
  using Source = std::pair<std::uint64_t, std::size_t>;
  std::vector<Source> order_;
  std::vector<GrainRecord<D>> arrived_, out_down_, out_up_;
  std::vector<std::uint32_t> new_index_;
  Bytes to_lower_, to_upper_, from_lower_, from_upper_;
  double ghost_width_ = 0.0, skin_ = 0.0;
  // With clumps: how far a member's centre may lie from its clump's centre, which decides its
  // rank (the largest offset, and half a skin for a centre that moved since the last build
  // when a run resumes from it). Ghost widths and the thinnest slab grow by it.
  bool clumped_ = false;
  double extent_ = 0.0;
  double min_slab() const { return ghost_width_ + extent_; }
  // Throws InputError when an inner slab is thinner than min_slab(): ghosts come from the
  // next slab only. `cause` says what made the width (every rank calls it alike).
  void refuse_thin_slabs(const std::string& cause) const;
  std::vector<ClumpRecord<D>> clumps_out_down_, clumps_out_up_, ghost_clumps_;
  // History records to carry into the next build: from the world as distributed, or of
  // grains that arrived.
  std::vector<PairRecord<D>> pairs_;
  std::vector<WallRecord<D>> walls_;
  std::vector<SparRecord<D>> spars_;
  // Ghost update: this rank's grains sent to the lower and upper neighbour (local indices, in
  // the order sent), and where the ghosts from each go.
  std::vector<std::uint32_t> send_lower_, send_upper_, recv_lower_, recv_upper_;
  Bytes halo_out_lower_, halo_out_upper_, halo_in_lower_, halo_in_upper_;  // kept: no allocation
  std::size_t halo_bytes_ = 0;
  // The rank's time in messages (waiting included: wall and CPU time) and its CPU time at the
  // end of the last window (NaN: not taken yet on this thread).
  double comm_seconds_ = 0.0, comm_cpu_seconds_ = 0.0, work_at_rebalance_ = 0.0;
  int builds_since_rebalance_ = 0;
  int uneven_windows_ = 0;  // windows in a row whose work was uneven
  double work_imbalance_ = 0.0;
  std::uint64_t cut_moves_ = 0;  // rebalances that moved a cut
  std::uint64_t migrated_ = 0;
};

}  // namespace geodem
