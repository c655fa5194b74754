// Settings of a `kind = "scene"` scenario, parsed once and immutable afterwards.
// Vectors are kept as plain lists here; the builder checks and converts them to
// the scenario's dimension.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/dim.hpp"
#include "clumps/grain_mix.hpp"
#include "io/checkpoint.hpp"
#include "io/toml_reader.hpp"
#include "materials/material.hpp"

namespace geodem {

using List = std::vector<double>;

// A list of the scenario's dimension as the engine's vector (the readers checked its size).
template <int D>
typename Dim<D>::Vec to_vec(const List& v) {
  typename Dim<D>::Vec x;
  for (int k = 0; k < D; ++k) x[k] = v[static_cast<std::size_t>(k)];
  return x;
}

struct PairSpec {
  std::string a, b;
  std::optional<double> friction, restitution, kn, kt;
};

struct WallSpec {
  std::string name, type, material;  // type: plane | segment | polyline
  List point, normal, velocity, from, to;
  std::vector<List> points;
  bool closed = false;
  double area = 0.0;
};

// A spar chain (geosynthetic sheet in 2D, cable in 3D) through `points`, each straight
// part cut into elements no longer than element_length (0: one element per part).
struct ChainSpec {
  std::string name, material;
  std::vector<List> points;
  double element_length = 0.0;
  double stiffness = 0.0;  // J
  double mass_per_length = 0.0;
  double thickness = 0.0;
  double bending = 0.0;
  std::vector<long long> held;  // node indices (negative: from the end) moving at `velocity`
  List velocity;
};

struct ParticleSpec {
  List position, velocity, angular_velocity;
  double radius = 0.0;
  std::string material;
  bool fixed = false;
};

// One clump placed explicitly.
struct ClumpSpec {
  std::string shape;  // template name
  List position, velocity, axis;
  double scale = 1.0;
  double angle_deg = 0.0;  // 2D: about z; 3D: about `axis`
  std::string material;
};

struct CloudSpec {
  std::string shape;  // "sphere"/"disc" or a clump template
  List lo, hi, velocity;
  std::size_t count = 0;
  double radius = 0.0;  // mean radius; 0: from porosity
  double porosity = 0.0;
  double fuzz = 0.0;
  std::string material;
};

// Grains read from a text file: whitespace- or comma-separated columns, '#' comments.
struct ParticleFileSpec {
  std::string path;                  // resolved against the scenario's folder
  std::vector<std::string> columns;  // names among id, x, y, z, radius, vx, vy, vz; "_" skips
  double radius = 0.0;               // when there is no radius column
  std::string material;
};

struct TimeSpec {
  double step = 0.0;  // 0: automatic
  double safety = 0.8;
  int update_interval = 50;
  double duration = 0.0;
  std::uint64_t steps = 0;
};

struct StopSpec {
  double unbalanced_below = 0.0;  // 0: off
  double kinetic_below = 0.0;     // J; 0: off
  double min_time = 0.0;
  // A stage with servos is at rest only when each holds its target within this fraction.
  double servo_tolerance = 0.01;
};

struct OutputSpec {
  std::uint64_t history_every = 1000;
  std::uint64_t vtk_every = 0;  // 0: first and last state only
  bool vtk = true;
  bool vtk_contacts = false;  // force chains: the contact network in each VTK frame
  // Grain displacements in the VTK frames: since the "start" of the run, since the start of
  // each "stage", or "none".
  std::string displacement_from = "start";
  bool plots = true;
  std::optional<std::pair<List, List>> measure_box;
};

// How a wall moves during a stage: at a set velocity, or as a plate held at a normal
// stress by a servo (controllers/plate_servo.hpp).
struct WallMotionSpec {
  std::string wall;
  List velocity;        // empty with a servo
  double stress = 0.0;  // servo target (Pa; N/m in 2D)
  bool servo = false;
  double max_speed = 0.0, gain = 0.5, integral_gain = 0.05;
};

// New velocity of a chain's held nodes during a stage.
struct ChainMotionSpec {
  std::string chain;
  List velocity;
};

// One stage of a scene: the edits made at its start, then a run until its duration or
// step count, or until its stop criteria hold. What a stage does not change stays.
struct StageSpec {
  std::string name;
  double duration = 0.0;    // s, from the stage's start (0: not limited by time)
  std::uint64_t steps = 0;  // steps of this stage (0: not limited)
  StopSpec stop;            // min_time counts from the stage's start
  std::optional<List> gravity;
  std::optional<double> friction, local_damping;
  std::vector<std::string> remove_walls;
  std::vector<std::pair<List, List>> remove_grains;  // boxes: grains with centres inside
  std::vector<WallSpec> add_walls;
  std::vector<CloudSpec> clouds;
  std::vector<WallMotionSpec> walls;
  std::vector<ChainMotionSpec> chains;
};

struct SceneSettings {
  std::string file;
  int dimension = 3;
  std::uint64_t seed = 1;
  TimeSpec time;
  StopSpec stop;
  List gravity;
  double local_damping = 0.0;
  double max_overlap = 0.5;  // stop as unstable beyond this overlap / smaller radius
  double skin = 0.4;         // Verlet skin, fraction of the mean radius
  int sort_interval = 10;    // renumber grains in cell order every N list builds
  std::vector<Material> materials;
  std::vector<PairSpec> pairs;
  std::vector<WallSpec> walls;
  std::vector<ChainSpec> chains;
  std::vector<ParticleSpec> particles;
  std::vector<TemplateSpec> templates;
  std::vector<ClumpSpec> clumps;
  bool bonds_initial = false;  // [bonds] create = "initial": bond touching grains at the start
  double bond_gap_tolerance = 0.0;
  std::vector<CloudSpec> clouds;
  std::vector<ParticleFileSpec> particle_files;
  std::vector<StageSpec> stages;  // empty: one stage given by [time] and [stop]
  // [start] checkpoint: grains, walls, chains and contacts of another scene run's checkpoint
  // (a file, or a run folder: its newest valid checkpoint); empty: none.
  std::string start_checkpoint;
  OutputSpec output;
  CheckpointSpec checkpoint;
  nlohmann::json resolved;  // every setting with its value, defaults included
};

// Reads one [[materials]] entry (also used by the lab tests' [material] table).
Material read_material(TableReader& t, const std::string& fallback_name);

// Reads a [checkpoint] table (keys every_steps, every_seconds, keep).
CheckpointSpec read_checkpoint_spec(TableReader& t);

// Parses and checks a scene scenario from its root table. A scene built to be filled and
// stepped from Python (from_python) may have no grains, no [time] table and no duration.
SceneSettings read_scene(const toml::table& root, const std::string& file,
                         bool from_python = false);

}  // namespace geodem
