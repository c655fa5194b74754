#include "scene/scene_stages.hpp"

#include <stdexcept>

#include "controllers/plate_servo.hpp"
#include "scene/build_scene.hpp"
#include "scene/scene_domain.hpp"
#include "world/world_editing.hpp"

namespace geodem {

template <int D>
std::vector<std::size_t> wall_indices(const World<D>& w, const std::string& name) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < w.walls.size(); ++i) {
    const std::string& n = w.walls[i].name;
    const bool segment_of = n.size() > name.size() + 1 && n.compare(0, name.size(), name) == 0 &&
                            n[name.size()] == '_' &&
                            n.find_first_not_of("0123456789", name.size() + 1) == std::string::npos;
    if (n == name || (w.walls[i].kind == WallKind::kSegment && segment_of)) out.push_back(i);
  }
  return out;
}

namespace {

template <int D>
std::vector<std::size_t> existing_walls(const World<D>& w, const std::string& name) {
  auto out = wall_indices(w, name);
  if (out.empty()) throw std::logic_error("no wall " + name);  // checked when reading
  return out;
}

}  // namespace

template <int D>
void start_stage(const SceneSettings& s, std::size_t k, World<D>& w, bool replay) {
  const StageSpec& st = s.stages[k];
  if (k > 0)
    for (const auto& m : s.stages[k - 1].walls)
      if (m.servo)
        for (auto i : wall_indices(w, m.wall)) w.walls[i].velocity.setZero();
  w.controllers.clear();
  w.tally_wall_dashpots = false;
  for (const auto& name : st.remove_walls) {
    auto idx = existing_walls(w, name);
    for (auto it = idx.rbegin(); it != idx.rend(); ++it) remove_wall(w, *it);
  }
  for (const auto& spec : st.add_walls)
    for (const auto& wall : walls_of<D>(spec, s.materials)) add_wall(w, wall);
  if (st.gravity) w.gravity = to_vec<D>(*st.gravity);
  if (st.local_damping) w.local_damping = *st.local_damping;
  if (st.friction) set_friction(w, *st.friction);
  if (!replay) {
    for (const auto& [lo, hi] : st.remove_grains) {
      const auto a = to_vec<D>(lo), b = to_vec<D>(hi);
      const auto& P = w.particles;
      remove_grains(w,
                    grains_where(w,
                                 [&](std::size_t i) {
                                   return (P.pos[i].array() >= a.array()).all() &&
                                          (P.pos[i].array() <= b.array()).all();
                                 }),
                    ContactHistory::kKeep);
    }
    if (!st.clouds.empty()) {
      // (a decomposed world: clear of the whole domain's grains, every rank alike)
      std::vector<Sphere<D>> placed = spheres_of<D>(w.domain ? domain_grains(w) : w.particles);
      Random rng(s.seed + 7919 * (k + 1));  // a stream of its own per stage
      const std::size_t before = w.particles.size(), clumps_before = w.clumps.size();
      for (std::size_t c = 0; c < st.clouds.size(); ++c)
        add_cloud(s, st.clouds[c], "stages." + std::to_string(k) + ".clouds." + std::to_string(c),
                  w, rng, placed);
      if (w.domain)
        keep_own_added_grains(w, before, clumps_before);
      else
        add_list_rows_for_new_grains(w, before);
    }
  }
  for (const auto& m : st.walls) {
    for (auto i : existing_walls(w, m.wall)) {
      if (!m.servo) {
        w.walls[i].velocity = to_vec<D>(m.velocity);
        continue;
      }
      w.walls[i].velocity.setZero();
      w.tally_wall_dashpots = true;  // the servo counts its contacts' dashpots
      w.controllers.push_back(
          std::make_shared<PlateServo<D>>(i, m.stress, m.max_speed, m.gain, m.integral_gain, true));
    }
  }
  for (const auto& m : st.chains) {
    auto& S = w.spars;
    for (const auto& c : S.chains) {
      if (c.name != m.chain) continue;
      for (std::uint32_t i = c.first_node; i < c.first_node + c.node_count; ++i)
        if (S.driven(i)) S.vel[i] = to_vec<D>(m.velocity);
    }
  }
}

template std::vector<std::size_t> wall_indices<2>(const World<2>&, const std::string&);
template std::vector<std::size_t> wall_indices<3>(const World<3>&, const std::string&);
template void start_stage<2>(const SceneSettings&, std::size_t, World<2>&, bool);
template void start_stage<3>(const SceneSettings&, std::size_t, World<3>&, bool);

}  // namespace geodem
