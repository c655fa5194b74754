#include "world/world_state.hpp"

namespace geodem {

template <int D>
struct IsPlainData<ContactExtra<D>> : std::true_type {};
template <int D>
struct IsPlainData<ContactStats<D>> : std::true_type {};

namespace {

// Checks on loading that a count rebuilt from the scenario matches the saved one.
template <class Archive>
void same_count(Archive& a, std::size_t n, const char* what) {
  std::uint64_t saved = n;
  a(saved);
  if (Archive::kLoading && saved != n)
    throw CheckpointError(std::string("the checkpoint has ") + std::to_string(saved) + " " + what +
                          ", the scenario " + std::to_string(n));
}
template <class Archive>
void same_name(Archive& a, const std::string& name, const char* what) {
  std::string saved = name;
  a(saved);
  if (Archive::kLoading && saved != name)
    throw CheckpointError(std::string(what) + " '" + saved + "' in the checkpoint is '" + name +
                          "' in the scenario");
}

// The saved count of a list: adopted (the list resized to it) or checked against the list's.
template <class Archive, class List>
void count_of(Archive& a, List& list, const char* what, bool adopt) {
  if (Archive::kLoading && adopt) {
    std::uint64_t n = 0;
    a(n);
    if (n > (1u << 24)) throw CheckpointError(std::string("implausible count of ") + what);
    list.resize(n);
  } else {
    same_count(a, list.size(), what);
  }
}
template <class Archive>
void name_of(Archive& a, std::string& name, const char* what, bool adopt) {
  if (adopt)
    a(name);
  else
    same_name(a, name, what);
}

// One list of fields for both directions. W is World<D> or const World<D>; the writer's
// operator() takes const references, so the const_cast below never writes.
template <class Archive, int D>
void visit(Archive& a, World<D>& w, bool adopt_walls = false) {
  auto& P = w.particles;
  a(P.pos), a(P.vel), a(P.angvel), a(P.force), a(P.torque), a(P.radius), a(P.inv_mass);
  a(P.inv_inertia), a(P.material), a(P.flags), a(P.pos_at_build), a(P.orient), a(P.id);
  a(P.next_id), a(P.clump), a(P.body_offset);

  auto& C = w.clumps;
  a(C.pos), a(C.vel), a(C.angvel), a(C.angmom), a(C.orient), a(C.rotation), a(C.force);
  a(C.torque), a(C.inv_mass), a(C.inertia), a(C.inv_inertia), a(C.volume), a(C.id);
  a(C.next_id), a(C.held);

  count_of(a, w.walls, "walls", adopt_walls);
  for (auto& wall : w.walls) {
    name_of(a, wall.name, "wall", adopt_walls);
    a(wall.kind), a(wall.point), a(wall.normal), a(wall.end), a(wall.across), a(wall.velocity);
    a(wall.material), a(wall.owns_end_vertex), a(wall.area), a(wall.force), a(wall.stiffness);
    a(wall.displacement);
  }

  auto& S = w.spars;
  a(S.pos), a(S.vel), a(S.force), a(S.mass), a(S.inertial_mass), a(S.flags), a(S.pos_at_build);
  a(S.node_a), a(S.node_b), a(S.prev), a(S.next), a(S.rest_length), a(S.stiffness);
  a(S.half_thickness), a(S.material), a(S.chain_of), a(S.rest_turn), a(S.tension);
  count_of(a, S.chains, "spar chains", adopt_walls);
  for (auto& c : S.chains) {
    name_of(a, c.name, "chain", adopt_walls);
    a(c.first_node), a(c.node_count), a(c.first_element), a(c.bending);
  }

  same_count(a, w.materials.size(), "materials");
  for (auto& m : w.materials) same_name(a, m.name, "material");
  a(w.pair_laws), a(w.wall_laws);

  auto& L = w.nlist;
  a(L.start), a(L.other), a(L.spring), a(L.wall_start), a(L.wall), a(L.wall_spring);
  a(L.extra), a(L.wall_extra), a(L.spar_start), a(L.spar), a(L.spar_spring), a(L.skin);
  a(L.builds), a(L.image);
  a(w.cell.periodic), a(w.cell.h), a(w.cell.vel_grad), a(w.cell.h_at_build);
  a(w.cell.reach_at_build);
  if constexpr (Archive::kLoading) w.collision_shares.built_for = CollisionShares::kNever;

  a(w.gravity), a(w.local_damping), a(w.dt), a(w.auto_dt), a(w.dt_safety);
  a(w.track_orientation), a(w.dt_update_interval), a(w.skin_factor), a(w.sort_interval);
  a(w.time), a(w.step), a(w.rebuild_needed), a(w.disp_bound), a(w.radius_growth);
  a(w.overlap_limit), a(w.contact_extras), a(w.broken_bonds), a(w.measure_this_step);
  a(w.stats), a(w.stage_seconds);
  if (adopt_walls) return;
  same_count(a, w.controllers.size(), "controllers");
  for (auto& c : w.controllers) {
    if constexpr (Archive::kLoading)
      c->load_state(a);
    else
      c->save_state(a);
  }
}

// Sizes that the step relies on: every per-grain array as long as the grains, the list's
// rows consistent. A checkpoint that passes its checksum but not these was not written by
// this program.
template <int D>
void check_sizes(const World<D>& w) {
  const auto& P = w.particles;
  const std::size_t n = P.pos.size();
  auto same = [&](std::size_t m, bool may_be_empty) {
    if (!(m == n || (may_be_empty && m == 0))) throw CheckpointError("inconsistent grain arrays");
  };
  same(P.vel.size(), false), same(P.angvel.size(), false), same(P.force.size(), false);
  same(P.torque.size(), false), same(P.radius.size(), false), same(P.inv_mass.size(), false);
  same(P.inv_inertia.size(), false), same(P.material.size(), false), same(P.flags.size(), false);
  same(P.pos_at_build.size(), false), same(P.id.size(), false), same(P.orient.size(), true);
  same(P.clump.size(), true), same(P.body_offset.size(), P.clump.empty());
  const auto& L = w.nlist;
  auto rows = [&](const std::vector<std::uint32_t>& start, std::size_t entries, bool optional) {
    if (optional && start.empty()) return;
    if (start.size() != n + 1 || start.back() != entries)
      throw CheckpointError("inconsistent neighbour list");
    for (std::size_t i = 0; i < n; ++i)
      if (start[i] > start[i + 1]) throw CheckpointError("inconsistent neighbour list");
  };
  rows(L.start, L.other.size(), true);
  rows(L.wall_start, L.wall.size(), true);
  rows(L.spar_start, L.spar.size(), true);
  for (auto j : L.other)
    if (j >= n) throw CheckpointError("neighbour list names a grain beyond the last");
  for (auto k : L.wall)
    if (k >= w.walls.size()) throw CheckpointError("neighbour list names a wall beyond the last");
  for (auto e : L.spar)
    if (e >= w.spars.elements()) throw CheckpointError("neighbour list names a missing element");
  if (w.cell.periodic && L.image.size() != L.other.size())
    throw CheckpointError("inconsistent periodic images");
  if (L.spring.size() != L.other.size() || L.wall_spring.size() != L.wall.size() ||
      L.spar_spring.size() != L.spar.size())
    throw CheckpointError("inconsistent contact history");
  for (auto m : P.material)
    if (m >= w.materials.size()) throw CheckpointError("grain material beyond the last");
  const std::size_t nm = w.materials.size();
  if (w.pair_laws.size() != nm * nm || w.wall_laws.size() != nm * w.walls.size())
    throw CheckpointError("inconsistent pair laws");
}

}  // namespace

template <int D>
void save_world_state(StateWriter& out, const World<D>& world) {
  visit(out, const_cast<World<D>&>(world));
}

template <int D>
void load_world_state(StateReader& in, World<D>& world) {
  visit(in, world);
  check_sizes(world);
  world.slab_crossing.release();
}

template <int D>
void load_world_state_with_walls(StateReader& in, World<D>& world) {
  visit(in, world, true);
  check_sizes(world);
  world.slab_crossing.release();
}

template void load_world_state_with_walls<2>(StateReader&, World<2>&);
template void load_world_state_with_walls<3>(StateReader&, World<3>&);
template void save_world_state<2>(StateWriter&, const World<2>&);
template void save_world_state<3>(StateWriter&, const World<3>&);
template void load_world_state<2>(StateReader&, World<2>&);
template void load_world_state<3>(StateReader&, World<3>&);

}  // namespace geodem
