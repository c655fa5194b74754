#include "scene/scene_settings.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "io/output_files.hpp"
#include "scene/grain_spec_reader.hpp"
#include "scene/scene_part_readers.hpp"
#include "scene/stage_settings.hpp"

namespace geodem {

Material read_material(TableReader& t, const std::string& fallback_name) {
  // Stiffnesses beyond any mineral's (1e15 Pa or N/m) only make the time step vanish.
  auto capped = [&t](const std::string& key, double v) {
    if (v > 1e15)
      t.fail(key,
             "expected a stiffness of at most 1e15 (stiffer than any mineral; the time step "
             "would vanish), got " +
                 format_number(v));
    return v;
  };
  Material m;
  m.name = t.string("name", fallback_name);
  m.density = t.positive("density", 2600.0);
  const std::string law = t.choice("law", "linear", {"linear", "hertz"});
  m.law = law == "hertz" ? LawKind::kHertz : LawKind::kLinear;
  m.friction = read_friction(t, 0.5);
  m.restitution = t.in_range("restitution", 1.0, 1e-6, 1.0);
  m.tangential_damping = t.boolean("tangential_damping", false);
  if (m.law == LawKind::kLinear) {
    if (t.has("kn") && t.has("young"))
      t.fail("kn", "give either constant stiffness 'kn' or contact modulus 'young', not both");
    if (t.has("kn")) {
      m.kn = capped("kn", t.positive("kn", 0.0));
      m.kt = t.has("kt") ? capped("kt", t.non_negative("kt", 0.0)) : -1.0;
      m.kt_over_kn = t.non_negative("kt_over_kn", 0.5);
    } else {
      m.young = capped("young", t.positive("young", 1e7));
      m.kt_over_kn = t.non_negative("kt_over_kn", 0.5);
    }
  } else {
    m.young = capped("young", t.positive("young", 1e7));
    m.poisson = t.in_range("poisson", 0.25, -0.99, 0.499);
  }
  m.rolling_friction = t.non_negative("rolling_friction", 0.0);
  m.twisting_friction = t.non_negative("twisting_friction", 0.0);
  m.rolling_stiffness = t.positive("rolling_stiffness", 1.0);
  m.normal_cohesion = t.non_negative("normal_cohesion", 0.0);
  m.shear_cohesion = t.non_negative("shear_cohesion", 0.0);
  m.cohesion_as_force = t.choice("cohesion_unit", "stress", {"stress", "force"}) == "force";
  if ((m.normal_cohesion > 0.0 || m.shear_cohesion > 0.0) && m.law != LawKind::kLinear)
    t.fail("normal_cohesion", "contact cohesion needs law = \"linear\"");
  return m;
}

SceneSettings read_scene(const toml::table& root, const std::string& file, bool from_python) {
  SceneSettings s;
  s.file = file;
  TableReader r(root, "", file, &s.resolved);
  r.choice("kind", "scene", {"scene"});
  s.dimension = static_cast<int>(r.integer("dimension", 3, 2, 3));
  s.seed = static_cast<std::uint64_t>(r.integer("seed", 1, 0, (1LL << 62)));
  r.string("title", "");
  const std::size_t D = static_cast<std::size_t>(s.dimension);

  // A scene in stages gives each stage its duration and stop criteria.
  const bool staged = r.has("stages");
  if (auto t = r.table("time")) {
    double step = 0.0;
    if (auto word = t->number_or_string("step", step, "auto")) {
      if (*word != "auto") t->fail("step", "expected a time step in seconds or \"auto\"");
    } else if (!(step > 0.0)) {
      t->fail("step", "expected a positive time step in seconds");
    }
    s.time.step = step;
    s.time.safety = t->in_range("safety", 0.8, 1e-3, 1.0);
    s.time.update_interval = static_cast<int>(t->integer("update_interval", 50, 1, 1000000));
    if (staged && (t->has("duration") || t->has("steps")))
      t->fail(t->has("duration") ? "duration" : "steps",
              "the scene has [[stages]]: give each stage its own 'duration' or 'steps'");
    s.time.duration = t->non_negative("duration", 0.0);
    s.time.steps = static_cast<std::uint64_t>(t->integer("steps", 0, 0, (1LL << 50)));
    if (!staged && !from_python && s.time.duration == 0.0 && s.time.steps == 0)
      t->fail("duration", "give the simulated time 'duration' (s) or a number of 'steps'");
    t->finish();
  } else if (!staged && !from_python) {
    r.fail("time", "missing [time] table (duration or steps)");
  }
  if (auto t = r.table("stop")) {
    if (staged)
      t->fail("unbalanced_below",
              "the scene has [[stages]]: give each stage its own [stages.stop] criteria");
    s.stop = read_stop(*t);
    t->finish();
  }
  s.gravity = List(D, 0.0);
  if (auto t = r.table("physics")) {
    s.gravity = t->numbers("gravity", s.gravity, D);
    if (s.gravity.size() != D) t->fail("gravity", "expected " + std::to_string(D) + " components");
    s.local_damping = t->in_range("local_damping", 0.0, 0.0, 0.99);
    s.max_overlap = t->in_range("max_overlap", 0.5, 1e-3, 2.0);
    t->finish();
  }
  if (auto t = r.table("neighbours")) {
    s.skin = t->in_range("skin", 0.4, 0.01, 10.0);
    s.sort_interval = static_cast<int>(t->integer("sort_interval", 10, 0, 1000000));
    t->finish();
  }

  std::set<std::string> names;
  for (auto& t : r.tables("materials")) {
    s.materials.push_back(read_material(t, "material" + std::to_string(s.materials.size())));
    if (!names.insert(s.materials.back().name).second)
      t.fail("name", "duplicate material name '" + s.materials.back().name + "'");
    if (s.dimension == 2 && s.materials.back().law == LawKind::kHertz)
      t.fail("law", "the Hertz-Mindlin law is for spheres; use \"linear\" in 2D");
    t.finish();
  }
  if (s.materials.empty()) r.fail("materials", "missing: define at least one [[materials]]");
  for (const auto& m : s.materials)
    if (m.law != s.materials.front().law)
      r.fail("materials", "materials '" + s.materials.front().name + "' and '" + m.name +
                              "' use different contact laws; all materials of a scene (walls "
                              "included) must use the same law");
  ScenePartContext parts;
  parts.dimension = s.dimension;
  parts.materials = names;
  parts.default_material = s.materials.front().name;
  auto material_name = [&](TableReader& t, const std::string& key) {
    return read_material_name(t, key, parts);
  };

  for (auto& t : r.tables("pairs")) {
    PairSpec p;
    const auto ab = t.strings("materials", 2);
    for (const auto& m : ab)
      if (!names.count(m)) t.fail("materials", "unknown material '" + m + "'");
    p.a = ab[0], p.b = ab[1];
    if (t.has("friction") || t.has("friction_deg")) p.friction = read_friction(t, 0.0);
    if (t.has("restitution")) p.restitution = t.in_range("restitution", 1.0, 1e-6, 1.0);
    if (t.has("kn")) p.kn = t.positive("kn", 1.0);
    if (t.has("kt")) p.kt = t.non_negative("kt", 0.0);
    s.pairs.push_back(p);
    t.finish();
  }

  auto vec = [&](TableReader& t, const std::string& key, const List& fallback) {
    return read_vector(t, key, fallback, s.dimension);
  };
  const List zero(D, 0.0);
  std::set<std::string> wall_names;
  for (auto& t : r.tables("walls")) {
    s.walls.push_back(read_wall(t, parts, s.walls.size()));
    if (!wall_names.insert(s.walls.back().name).second)
      t.fail("name", "duplicate wall name '" + s.walls.back().name + "'");
    t.finish();
  }

  std::set<std::string> chain_names;
  for (auto& t : r.tables("chains")) {
    s.chains.push_back(read_chain(t, parts, s.chains.size()));
    if (!chain_names.insert(s.chains.back().name).second)
      t.fail("name", "duplicate chain name '" + s.chains.back().name + "'");
    t.finish();
  }

  for (auto& t : r.tables("particles")) {
    ParticleSpec p;
    p.position = vec(t, "position", zero);
    if (!t.has("radius")) t.fail("radius", "missing; expected the grain radius (m)");
    p.radius = t.positive("radius", 0.0);
    p.velocity = vec(t, "velocity", zero);
    p.angular_velocity = t.numbers("angular_velocity", List(D == 2 ? 1 : 3, 0.0), D == 2 ? 1 : 3);
    if (p.angular_velocity.size() != (D == 2 ? 1u : 3u))
      t.fail("angular_velocity", D == 2 ? "expected 1 value in 2D" : "expected 3 values in 3D");
    p.material = material_name(t, "material");
    p.fixed = t.boolean("fixed", false);
    s.particles.push_back(p);
    t.finish();
  }

  s.templates = read_templates(r, s.dimension);
  parts.templates = &s.templates;
  for (auto& t : r.tables("clumps")) {
    s.clumps.push_back(read_clump(t, parts));
    t.finish();
  }
  if (auto b = r.table("bonds")) {
    s.bonds_initial = b->choice("create", "initial", {"none", "initial"}) == "initial";
    s.bond_gap_tolerance = b->in_range("gap_tolerance", 0.0, 0.0, 0.5);
    b->finish();
  }

  for (auto& t : r.tables("clouds")) {
    s.clouds.push_back(read_cloud(t, parts));
    t.finish();
  }
  for (auto& t : r.tables("particle_files")) {
    ParticleFileSpec f;
    const std::string name = t.string("file", "");
    if (name.empty()) t.fail("file", "missing; expected the path of a text file of grains");
    const std::filesystem::path p(name);
    f.path = p.is_absolute() ? name : (std::filesystem::path(file).parent_path() / p).string();
    std::error_code ec;  // a name the system cannot take is not found, not a crash
    if (!std::filesystem::is_regular_file(f.path, ec)) t.fail("file", "file not found: " + f.path);
    std::vector<std::string> fallback = D == 3 ? std::vector<std::string>{"x", "y", "z", "radius"}
                                               : std::vector<std::string>{"x", "y", "radius"};
    // A table written by a scene (io/particle_table.hpp) names its columns in a comment.
    if (!t.has("columns")) {
      std::ifstream in(f.path);
      for (std::string line; std::getline(in, line) && (line.empty() || line[0] == '#');)
        if (line.rfind("# columns:", 0) == 0) {
          std::istringstream words(line.substr(10));
          std::vector<std::string> header;
          for (std::string c; words >> c;) header.push_back(c);
          if (!header.empty()) fallback = header;
        }
    }
    f.columns = t.strings("columns", fallback);
    const std::set<std::string> known = {"id", "x",  "y",  "z",        "radius",
                                         "vx", "vy", "vz", "material", "_"};
    std::set<std::string> seen;
    for (const auto& c : f.columns) {
      if (!known.count(c))
        t.fail("columns", "unknown column '" + c + "'; known: id x y z radius vx vy vz material _");
      if (c != "_" && !seen.insert(c).second) t.fail("columns", "column '" + c + "' given twice");
    }
    for (const char* c : {"x", "y", "z"})
      if ((D == 3 || std::string(c) != "z") && !seen.count(c))
        t.fail("columns", std::string("missing column '") + c + "'");
    if (!seen.count("radius")) {
      if (!t.has("radius")) t.fail("radius", "no radius column: give the grains' 'radius'");
      f.radius = t.positive("radius", 0.0);
    }
    f.material = material_name(t, "material");
    s.particle_files.push_back(f);
    t.finish();
  }
  if (auto t = r.table("start")) {
    const std::string name = t->string("checkpoint", "");
    if (name.empty())
      t->fail("checkpoint", "missing; expected a checkpoint file or the folder of a scene run");
    const std::filesystem::path p(name);
    s.start_checkpoint =
        p.is_absolute() ? name : (std::filesystem::path(file).parent_path() / p).string();
    std::error_code ec;
    if (!std::filesystem::exists(s.start_checkpoint, ec))
      t->fail("checkpoint", "not found: " + s.start_checkpoint);
    if (!s.particles.empty() || !s.clouds.empty() || !s.particle_files.empty() ||
        !s.clumps.empty() || !s.chains.empty())
      t->fail("checkpoint",
              "a scene that starts from a checkpoint takes its grains and chains from it: add "
              "grains in a stage ([[stages.clouds]]) instead of [[particles]], [[clumps]], "
              "[[clouds]], [[particle_files]] or [[chains]]");
    t->finish();
  } else if (!from_python && s.particles.empty() && s.clouds.empty() && s.particle_files.empty() &&
             s.clumps.empty()) {
    r.fail("particles",
           "the scene has no grains: add [[particles]], [[clumps]] or [[clouds]], or start "
           "from another run's checkpoint ([start] checkpoint)");
  }

  if (staged) s.stages = read_stages(r, parts, s);

  if (auto t = r.table("output")) {
    s.output.history_every =
        static_cast<std::uint64_t>(t->integer("history_every", 1000, 1, (1LL << 50)));
    s.output.vtk_every = static_cast<std::uint64_t>(t->integer("vtk_every", 0, 0, (1LL << 50)));
    s.output.vtk = t->boolean("vtk", true);
    s.output.vtk_contacts = t->boolean("vtk_contacts", false);
    s.output.displacement_from =
        t->choice("displacement_from", "start", {"start", "stage", "none"});
    s.output.plots = t->boolean("plots", true);
    if (auto b = t->table("measure_box")) {
      s.output.measure_box = read_box(*b, s.dimension);
      b->finish();
    }
    t->finish();
  }
  if (auto t = r.table("checkpoint")) {
    s.checkpoint = read_checkpoint_spec(*t);
    t->finish();
  }
  r.finish();
  return s;
}

CheckpointSpec read_checkpoint_spec(TableReader& t) {
  CheckpointSpec c;
  c.every_steps = static_cast<std::uint64_t>(t.integer("every_steps", 0, 0, (1LL << 50)));
  c.every_seconds = t.non_negative("every_seconds", 0.0);
  c.keep = static_cast<int>(t.integer("keep", 2, 1, 1000));
  return c;
}

}  // namespace geodem
