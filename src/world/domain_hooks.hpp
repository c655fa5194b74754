// What the step asks of a spatial decomposition of the world over several processes
// (domain/slab_domain.hpp): the rank's world holds the grains it owns and ghost copies of
// its neighbours' grains near its boundaries. Called a few times per step at most (never
// per grain or contact): the step stays one function for one process and for many.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/exact_sum.hpp"

namespace geodem {

template <int D>
struct World;

template <int D>
class DomainHooks {
 public:
  virtual ~DomainHooks() = default;
  // Whether this or any other rank needs a neighbour-list build (all build together).
  virtual bool any_rank(bool here) = 0;
  // The smallest of every rank's value (the automatic time step).
  virtual double min_over_ranks(double here) = 0;
  // Every rank's sums added, exactly (base/exact_sum.hpp), in place.
  virtual void sum(std::vector<ExactSum>& sums) = 0;
  // Every rank's count added (each rank counts what it owns).
  std::uint64_t count_over_ranks(std::uint64_t here) {
    std::vector<ExactSum> n(1);
    n[0].add(static_cast<double>(here));
    sum(n);
    return static_cast<std::uint64_t>(n[0].value());
  }
  // The first non-empty text of the ranks in rank order ("" when all are empty): the
  // diagnosis that stops every rank when one meets an instability.
  virtual std::string first_text(const std::string& here) = 0;
  virtual int rank() const = 0;
  virtual int ranks() const = 0;
  // The skin of every rank's list (from all grains' radii, not only this rank's).
  virtual double skin() const = 0;
  // Before a build: grains that left the rank's region go to their new owner with their
  // contact history, ghosts are renewed, and the list's old rows are rewritten for the new
  // numbering, so that the build merges the history as usual.
  virtual void before_build(World<D>& world) = 0;
  // Grains were removed (world/world_editing.hpp) by a rule on their state, which every rank
  // applies alike to its grains and ghosts: the grains left are the old indices `keep`, in
  // order. The next step builds the list (rebuild_needed).
  virtual void grains_kept(World<D>& world, const std::vector<std::uint32_t>& keep) = 0;
  // After integration: the ghosts take their owners' new positions and velocities.
  virtual void after_integration(World<D>& world) = 0;
  // How many times the ranks' regions were moved to even their work (the summary's timing).
  virtual std::uint64_t region_moves() const { return 0; }
};

}  // namespace geodem
