#include "scene/scene_start.hpp"

#include <filesystem>
#include <vector>

#include "base/error.hpp"
#include "io/checkpoint.hpp"
#include "world/world_editing.hpp"
#include "world/world_state.hpp"

namespace geodem {

namespace {

Checkpoint read_start(const SceneSettings& s) {
  namespace fs = std::filesystem;
  const fs::path p(s.start_checkpoint);
  std::error_code ec;
  if (!fs::is_directory(p, ec)) return read_checkpoint(p.string());
  // A run folder, or its checkpoint folder: the newest valid checkpoint.
  const fs::path run = fs::is_directory(p / "checkpoint", ec) ? p : p.parent_path();
  std::vector<std::string> skipped;
  return load_latest_checkpoint(run.string(), &skipped);
}

}  // namespace

template <int D>
void start_from_checkpoint(const SceneSettings& s, World<D>& w) {
  auto fail = [&](const std::string& what) {
    throw InputError(s.file, 0, "start.checkpoint", s.start_checkpoint + ": " + what);
  };
  Checkpoint c;
  try {
    c = read_start(s);
  } catch (const CheckpointError& e) {
    fail(std::string("no readable checkpoint (") + e.what() + ")");
  }
  if (c.kind != "scene")
    fail("a checkpoint of a \"" + c.kind + "\" run; a scene starts from a scene's checkpoint");
  if (c.dimension != D)
    fail("a " + std::to_string(c.dimension) + "D checkpoint for a " + std::to_string(D) +
         "D scene");
  // What the scenario sets, kept across the load (which brings the saved run's values).
  const std::vector<Wall<D>> own_walls = w.walls;
  const std::vector<PairLaw> pair_laws = w.pair_laws;
  auto copy_settings = [](const World<D>& from, World<D>& to) {
    to.gravity = from.gravity, to.local_damping = from.local_damping, to.dt = from.dt;
    to.auto_dt = from.auto_dt, to.dt_safety = from.dt_safety;
    to.dt_update_interval = from.dt_update_interval, to.skin_factor = from.skin_factor;
    to.sort_interval = from.sort_interval, to.overlap_limit = from.overlap_limit;
  };
  World<D> settings;
  copy_settings(w, settings);
  try {
    StateReader in(c.world.data(), c.world.size());
    load_world_state_with_walls(in, w);
  } catch (const CheckpointError& e) {
    fail(std::string("does not fit this scene: ") + e.what() +
         " (the scene's [[materials]] must be the run's, by name and in order)");
  }
  copy_settings(settings, w);
  w.time = 0.0, w.step = 0;
  w.controllers.clear();
  w.pair_laws = pair_laws;
  resolve_wall_laws(w);  // the saved walls with this scenario's materials
  for (const auto& wall : own_walls) {
    for (const auto& other : w.walls)
      if (other.name == wall.name)
        throw InputError(s.file, 0, "walls",
                         "wall '" + wall.name + "' is already a wall of the checkpoint " +
                             s.start_checkpoint + ": give it another name");
    add_wall(w, wall);
  }
  w.rebuild_needed = true;
}

template void start_from_checkpoint<2>(const SceneSettings&, World<2>&);
template void start_from_checkpoint<3>(const SceneSettings&, World<3>&);

}  // namespace geodem
