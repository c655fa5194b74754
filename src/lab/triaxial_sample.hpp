// The sample of the triaxial kind and its element tests (lab/run_triaxial.cpp): the walls of
// the box or the periodic cell, and a loose random cloud of grains (round grains of one
// mean radius, or a mix of clump kinds) at the initial porosity, in a world set up for the
// automatic time step.
#pragma once

#include <stdexcept>

#include "base/error.hpp"
#include "base/random.hpp"
#include "clumps/grain_mix.hpp"
#include "lab/triaxial_settings.hpp"
#include "particles/random_cloud.hpp"
#include "walls/lab_box.hpp"
#include "world/world.hpp"

namespace geodem {

template <int D>
LabBox<D> build_triaxial_sample(World<D>& w, const TriaxialSettings& s, int threads) {
  using Vec = typename Dim<D>::Vec;
  LabBox<D> box;
  w.materials = {s.grain, s.wall};
  Vec size;
  for (int k = 0; k < D; ++k) size[k] = s.box[static_cast<std::size_t>(k)];
  box = s.periodic ? LabBox<D>::periodic_cell(w, size) : LabBox<D>::add_to(w, Vec::Zero(), size, 1);
  w.resolve_pair_laws();
  Random rng(s.seed);
  try {
    if (s.grains.round_only()) {
      const double mean =
          mean_radius_for_porosity<D>(size.prod(), s.count, s.initial_porosity, s.radius_fuzz);
      const auto grains = random_cloud<D>(Vec::Zero(), size, s.count, mean, s.radius_fuzz, rng);
      w.particles.reserve(grains.size());
      for (const auto& g : grains) w.particles.add(g.centre, g.radius, s.grain.density, 0);
    } else {
      add_random_grains<D>(w, resolve_kinds<D>(s.grains), Vec::Zero(), size, s.count,
                           s.initial_porosity, s.radius_fuzz, s.grain.density, 0, rng);
    }
  } catch (const std::runtime_error& e) {
    throw InputError(s.file, 0, "sample.initial_porosity", e.what());
  }
  w.auto_dt = true;
  w.dt_safety = s.dt_safety;
  w.dt_update_interval = s.dt_update_interval;
  w.sort_interval = 10;
  w.threads = threads;
  return box;
}

}  // namespace geodem
