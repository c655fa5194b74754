// The simulated world: its settings, its state (grains, walls, materials, contacts, time),
// the step's scratch and its report. The time step (world/step.cpp) advances it; the engine
// never reads files.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/dim.hpp"
#include "base/parallel.hpp"
#include "clumps/clumps.hpp"
#include "clumps/collision_shares.hpp"
#include "contacts/neighbour_list.hpp"
#include "materials/material.hpp"
#include "particles/particles.hpp"
#include "structures/spar_chains.hpp"
#include "walls/walls.hpp"
#include "world/domain_hooks.hpp"
#include "world/periodic_cell.hpp"

namespace geodem {

// Boundary controllers (servo walls, strain control, radius growth...) act once per
// step after the contact forces, before integration.
// A controller whose state evolves (a servo's integral term) saves it in checkpoints;
// its settings come from the scenario when the run is rebuilt.
template <int D>
struct World;
class StateWriter;
class StateReader;
template <int D>
class Controller {
 public:
  virtual ~Controller() = default;
  virtual void apply(World<D>& world) = 0;
  virtual void save_state(StateWriter&) const {}
  virtual void load_state(StateReader&) {}
  // Wall `index` is being removed (world/world_editing.hpp): a controller of that wall
  // answers true and is dropped; one of a later wall renumbers it.
  virtual bool wall_removed(std::size_t /*index*/) { return false; }
  // True when apply() reads nothing of the grains and changes nothing but walls and its own
  // state: the step may then move the grains before it runs (world/step.cpp; never in a
  // periodic cell, whose stress a servo reads).
  virtual bool walls_only() const { return false; }
};

enum class Stage : int {
  kNeighbours,
  kContactForces,
  kStructures,
  kControllers,
  kIntegration,
  kRecorders,
  kCount
};
inline const char* stage_name(Stage s) {
  static const char* names[] = {"neighbour search", "contact forces", "structures",
                                "controllers",      "integration",    "recorders"};
  return names[static_cast<int>(s)];
}

// What the contact force stage measured on a step where measuring was asked.
template <int D>
struct ContactStats {
  typename Dim<D>::Tensor fabric_stress = Dim<D>::Tensor::Zero();  // sum of l (x) f
  double sum_force = 0.0;    // sum of |f| over grain-grain and grain-wall contacts
  std::size_t contacts = 0;  // grain-grain contacts
  std::size_t wall_contacts = 0;
  std::size_t spar_contacts = 0;  // grain-spar element contacts
  double elastic_energy = 0.0;    // normal springs only (exact without friction and dashpots)
};

// A contribution computed in one slab of grains for a body outside it (a force and a
// torque, or a stiffness): kept per slab and added afterwards in slab order, so that sums
// do not depend on the thread count (base/parallel.hpp).
template <int D>
struct SlabCrossing {
  typename Dim<D>::Vec a;
  typename Dim<D>::Rot b;
  std::uint32_t body;
};

// The world is four parts, each with one owner; World joins them so that the engine's
// loops read one object.
//
// Settings: how the step runs, set by a builder from a scenario (and by a stage or Python
// between steps); the step reads them and never writes them.
template <int D>
struct WorldSettings {
  using Vec = typename Dim<D>::Vec;
  Vec gravity = Vec::Zero();
  double local_damping = 0.0;  // Cundall's non-viscous damping coefficient alpha
  bool auto_dt = false;
  double dt_safety = 0.8;
  int dt_update_interval = 50;
  // Integrate grain orientations. Off by default: a round grain's orientation does not
  // enter its dynamics (forces depend on angular velocity only), and the update is about
  // a tenth of a step's cost; whatever reads orientations (clumps, output) turns it on.
  // Untracked, no orientation is stored (Particles::orient stays empty).
  bool track_orientation = false;
  double skin_factor = 0.4;  // skin as a fraction of the mean radius
  // Every this many neighbour-list builds, grains are renumbered in cell order so
  // that neighbours sit close in memory (0: never; grain indices then stay fixed).
  int sort_interval = 0;
  // Threads of the step's loops (base/parallel.hpp); results do not depend on it.
  int threads = 1;
  // Instability watch: an overlap beyond this fraction of the smaller radius stops
  // the run (the contact force stage notes the first offender in the report).
  double overlap_limit = 0.5;
  // Sum each wall's contact dashpots (Wall::dashpot) in the force stage: only a servo that
  // counts them asks (a square root per wall contact otherwise spared).
  bool tally_wall_dashpots = false;
  // The force stage's grains in one slab instead of slab_length(n) each: every grain then sums
  // its contacts in the order of its partners' indices alone.
  bool one_slab = false;
  // Set when the world is one rank's part of a decomposed domain (domain/slab_domain.hpp).
  std::shared_ptr<DomainHooks<D>> domain;
  // The slabs' starts (then n at the end), when a decomposed domain sets them: a rank's slabs
  // follow its grains' keys, so that each grain sums its contacts in the same order on every
  // rank (its slab differs from the uniform one of a rank that holds other grains).
  std::vector<std::uint32_t> slab_starts;

  // The slabs of the force and time-step stages (base/parallel.hpp).
  SlabPlan slab_plan(std::size_t n) const {
    if (!slab_starts.empty()) {
      if (slab_starts.back() != n) throw std::logic_error("the domain's slabs miss grains");
      return SlabPlan::given(n, slab_starts);
    }
    return SlabPlan::uniform(n, one_slab ? std::max<std::size_t>(n, 1) : 0);
  }
};

// State: what the step advances and a checkpoint saves (world/world_state.cpp): the bodies,
// their materials and pair laws, the contacts with their history, the clock and the
// neighbour list's counters, the controllers.
template <int D>
struct WorldState {
  Particles<D> particles;
  Clumps<D> clumps;  // rigid bodies made of grains of `particles`
  std::vector<Wall<D>> walls;
  SparChains<D> spars;  // geosynthetic sheets / cables; their materials are in `materials`
  std::vector<Material> materials;
  std::vector<PairLaw> pair_laws;  // materials x materials
  std::vector<PairLaw> wall_laws;  // materials x walls
  NeighbourList<D> nlist;
  PeriodicCell<D> cell;  // periodic boundaries when cell.periodic
  // Shared so that a world can be copied (a prepared sample reused for several tests).
  std::vector<std::shared_ptr<Controller<D>>> controllers;

  double dt = 0.0;
  double time = 0.0;
  std::uint64_t step = 0;
  bool rebuild_needed = true;
  // Largest grain displacement since the last build: bounded cheaply each step by
  // the sum of max |v| dt, measured exactly only when the bound reaches half the skin.
  double disp_bound = 0.0;
  // A decomposed world: the last integration's bound (max |v| dt over this rank's grains),
  // added to disp_bound as the largest over all ranks at the next list check, so that every
  // rank holds the same bound and decides alike for any number of ranks.
  double last_move = 0.0;
  // Growth of the largest radius since the last build (radius-growth compaction): gaps
  // close by at most twice this, so it counts like a displacement.
  double radius_growth = 0.0;
  // Rolling springs and bonds stored per contact (NeighbourList::extra); set by
  // update_contact_extras(), which must be called again if pair laws are edited.
  bool contact_extras = false;
  std::uint64_t broken_bonds = 0;  // bonds broken since the start

  // The branch vector from grain i to the partner j of list entry k: x_j - x_i, to the
  // partner's image in a periodic cell.
  typename Dim<D>::Vec branch(std::size_t i, std::size_t j, std::size_t k) const {
    typename Dim<D>::Vec d = particles.pos[j] - particles.pos[i];
    if (cell.periodic && !nlist.image[k].home()) d += cell.shift(nlist.image[k]);
    return d;
  }

  const PairLaw& pair_law(std::uint16_t a, std::uint16_t b) const {
    return pair_laws[a * materials.size() + b];
  }
  const PairLaw& wall_law(std::uint16_t mat, std::size_t w) const {
    return wall_laws[mat * walls.size() + w];
  }

  // Resolves the pair tables; call after materials and walls are set. Explicit
  // pair laws can be put in the tables afterwards.
  void resolve_pair_laws() {
    const std::size_t nm = materials.size();
    pair_laws.resize(nm * nm);
    for (std::size_t a = 0; a < nm; ++a)
      for (std::size_t b = 0; b < nm; ++b)
        pair_laws[a * nm + b] = combine(materials[a], materials[b]);
    wall_laws.resize(nm * walls.size());
    for (std::size_t a = 0; a < nm; ++a)
      for (std::size_t w = 0; w < walls.size(); ++w)
        wall_laws[a * walls.size() + w] = combine(materials[a], materials[walls[w].material]);
    for (auto* table : {&pair_laws, &wall_laws})
      for (auto& law : *table) law.per_unit_thickness = D == 2;
    update_contact_extras();
    rebuild_needed = true;
  }
  // Contacts carry rolling springs and bond states only when some pair law needs them.
  void update_contact_extras() {
    contact_extras = false;
    for (auto* table : {&pair_laws, &wall_laws})
      for (const auto& law : *table) contact_extras |= law.rolling() || law.cohesive();
  }
};

// Scratch: derived each step from the state, kept between steps only so that the step
// allocates nothing; never read as a result.
template <int D>
struct StepScratch {
  // Per list entry, how many member contacts of a clump carry the same collision (derived
  // from the list and the positions each step; see clumps/collision_shares.hpp).
  CollisionShares collision_shares;
  // Per-slab crossing contributions of the force stage and the automatic time step.
  mutable SlabCrossings<SlabCrossing<D>> slab_crossing;
  // A list build's copy of the old rows (their history), its parts of the rows and, while the
  // build runs, the force arrays given back: kept mapped between builds while together they weigh
  // less than kSmallBuildScratch (broadphase/neighbour_search.cpp), given back otherwise.
  NeighbourList<D> old_rows;
  // A parallel build's rows of threads 1, 2, ... (thread 0 writes into the list itself).
  struct ListPart {
    std::vector<std::uint32_t> other, wall;
  };
  std::vector<ListPart> list_parts;
  bool keep_build_scratch = false;
  // The step asks the force stage to move each slab's grains as soon as their forces are
  // complete (world/step.cpp says when it may); the stage then notes that it moved them, for
  // the integration to skip its own move. Either move keeps each slab's largest speed squared.
  bool move_in_force_stage = false, grains_moved = false;
  std::vector<double> slab_vmax2;
  // Each clump's members in grain order, remade after each neighbour-list build (grains are
  // renumbered there) or when the counts changed: the clump integration sums them clump by
  // clump, on several threads, in the order of the grains.
  struct ClumpMembers {
    std::vector<std::uint32_t> start, grain;
    std::uint64_t builds = ~std::uint64_t{0};
    std::size_t grains = 0, clumps = 0;
  } clump_members;
};

// Report: what the last step measured, for the runner's records; the runner asks for the
// costly part (measure_this_step) on the steps it records.
template <int D>
struct StepReport {
  bool measure_this_step = false;
  ContactStats<D> stats;
  std::array<double, static_cast<int>(Stage::kCount)> stage_seconds{};
  // The first overlap beyond overlap_limit (grain, partner: a grain, or -1 - wall index).
  std::int64_t overlap_offender = -1, overlap_partner = -1;
  double overlap_ratio = 0.0;
  // A decomposed domain: some rank met such an overlap this step (all ranks stop together).
  bool overlap_elsewhere = false;
  // In a periodic cell, every step (the cell servo's feedback): the sum over grain-grain
  // contacts of d (x) f (the fabric stress times the volume, members' centres as the grains'
  // centres), and of kn (d_k n_k)^2, the stiffness of the packing against a homogeneous strain
  // of component k (times the volume).
  typename Dim<D>::Tensor cell_fabric = Dim<D>::Tensor::Zero();
  typename Dim<D>::Vec cell_stiffness = Dim<D>::Vec::Zero();
};

template <int D>
struct World : WorldSettings<D>, WorldState<D>, StepScratch<D>, StepReport<D> {
  using Vec = typename Dim<D>::Vec;
};

}  // namespace geodem
