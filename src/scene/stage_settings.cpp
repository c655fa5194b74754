#include "scene/stage_settings.hpp"

#include <map>

namespace geodem {

std::vector<StageSpec> read_stages(TableReader& root, const ScenePartContext& parts,
                                   const SceneSettings& scene) {
  const int D = scene.dimension;
  // The walls present as the stages go: name -> its spec (a polyline counts as one).
  std::map<std::string, WallSpec> present;
  for (const auto& w : scene.walls) present[w.name] = w;
  std::map<std::string, const ChainSpec*> chains;
  for (const auto& c : scene.chains) chains[c.name] = &c;
  std::vector<StageSpec> stages;
  auto tables = root.tables("stages");
  if (tables.empty()) root.fail("stages", "expected at least one [[stages]] table");
  for (auto& t : tables) {
    StageSpec st;
    st.name = t.string("name", "stage" + std::to_string(stages.size() + 1));
    for (const auto& other : stages)
      if (other.name == st.name) t.fail("name", "duplicate stage name '" + st.name + "'");
    st.duration = t.non_negative("duration", 0.0);
    st.steps = static_cast<std::uint64_t>(t.integer("steps", 0, 0, (1LL << 50)));
    if (st.duration == 0.0 && st.steps == 0)
      t.fail("duration",
             "give the stage's 'duration' (s) or 'steps' (its stop criteria may end it sooner)");
    if (auto s = t.table("stop")) {
      st.stop = read_stage_stop(*s);
      s->finish();
    }
    if (t.has("gravity")) st.gravity = read_vector(t, "gravity", {}, D);
    if (t.has("friction") || t.has("friction_deg")) st.friction = read_friction(t, 0.0);
    if (t.has("local_damping")) st.local_damping = t.in_range("local_damping", 0.0, 0.0, 0.99);

    for (const auto& name : t.strings("remove_walls", std::vector<std::string>{})) {
      if (!present.erase(name))
        t.fail("remove_walls", "no wall '" + name + "' is present at this stage");
      st.remove_walls.push_back(name);
    }
    for (auto& b : t.tables("remove_grains")) {
      st.remove_grains.push_back(read_box(b, D));
      b.finish();
    }
    for (auto& w : t.tables("add_walls")) {
      WallSpec spec = read_wall(w, parts, scene.walls.size() + st.add_walls.size());
      if (present.count(spec.name))
        w.fail("name", "a wall '" + spec.name + "' is already present at this stage");
      present[spec.name] = spec;
      st.add_walls.push_back(spec);
      w.finish();
    }
    for (auto& c : t.tables("clouds")) {
      st.clouds.push_back(read_cloud(c, parts));
      c.finish();
    }
    for (auto& w : t.tables("walls")) {
      WallMotionSpec m;
      m.wall = w.string("name", "");
      auto it = present.find(m.wall);
      if (it == present.end()) w.fail("name", "no wall '" + m.wall + "' is present at this stage");
      if (w.has("velocity") == w.has("servo_stress"))
        w.fail("velocity", "give the wall either a 'velocity' or a 'servo_stress' (Pa)");
      if (w.has("velocity")) {
        m.velocity = read_vector(w, "velocity", {}, D);
      } else {
        if (it->second.type != "plane" || !(it->second.area > 0.0))
          w.fail("servo_stress",
                 "a servo drives a plane wall with an 'area' (m^2; m in 2D), and wall '" + m.wall +
                     "' is not one");
        m.servo = true;
        m.stress = w.non_negative("servo_stress", 0.0);
        if (!w.has("max_speed"))
          w.fail("max_speed", "missing; expected the servo's speed cap (m/s)");
        m.max_speed = w.positive("max_speed", 0.0);
        m.gain = w.in_range("gain", 0.5, 1e-3, 1.0);
        m.integral_gain = w.in_range("integral_gain", 0.05, 0.0, 1.0);
      }
      for (const auto& other : st.walls)
        if (other.wall == m.wall) w.fail("name", "wall '" + m.wall + "' is set twice");
      st.walls.push_back(m);
      w.finish();
    }
    for (auto& c : t.tables("chains")) {
      ChainMotionSpec m;
      m.chain = c.string("name", "");
      auto it = chains.find(m.chain);
      if (it == chains.end()) c.fail("name", "no chain '" + m.chain + "'");
      if (it->second->held.empty())
        c.fail("name", "chain '" + m.chain + "' has no held nodes to move (its key 'held')");
      m.velocity = read_vector(c, "velocity", {}, D);
      st.chains.push_back(m);
      c.finish();
    }
    stages.push_back(st);
    t.finish();
  }
  return stages;
}

}  // namespace geodem
