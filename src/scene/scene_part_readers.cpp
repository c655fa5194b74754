#include "scene/scene_part_readers.hpp"

#include <cmath>
#include <numbers>

#include "scene/grain_spec_reader.hpp"

namespace geodem {

List read_vector(TableReader& t, const std::string& key, const List& fallback, int dimension) {
  const auto D = static_cast<std::size_t>(dimension);
  List v = t.numbers(key, fallback, D);
  if (v.size() != D)
    t.fail(key, "expected " + std::to_string(D) + " components for dimension " + std::to_string(D));
  return v;
}

std::string read_material_name(TableReader& t, const std::string& key, const ScenePartContext& c) {
  const std::string m = t.string(key, c.default_material);
  if (!c.materials.count(m)) t.fail(key, "unknown material '" + m + "'");
  return m;
}

double read_friction(TableReader& t, double fallback) {
  if (t.has("friction") && t.has("friction_deg"))
    t.fail("friction_deg", "give either 'friction' (coefficient) or 'friction_deg', not both");
  if (t.has("friction_deg"))
    return std::tan(t.in_range("friction_deg", 0.0, 0.0, 89.9) * std::numbers::pi / 180.0);
  return t.non_negative("friction", fallback);
}

WallSpec read_wall(TableReader& t, const ScenePartContext& c, std::size_t index) {
  const int D = c.dimension;
  const List zero(static_cast<std::size_t>(D), 0.0);
  WallSpec w;
  w.name = t.string("name", "wall" + std::to_string(index));
  w.type = t.choice("type", "plane", {"plane", "segment", "polyline"});
  w.material = read_material_name(t, "material", c);
  w.velocity = read_vector(t, "velocity", zero, D);
  w.area = t.non_negative("area", 0.0);
  if (w.type == "plane") {
    w.point = read_vector(t, "point", zero, D);
    w.normal = read_vector(t, "normal", zero, D);
    double n2 = 0.0;
    for (double x : w.normal) n2 += x * x;
    if (n2 == 0.0) t.fail("normal", "expected a non-zero normal vector");
  } else {
    if (D != 2) t.fail("type", "segments and polylines are 2D boundaries");
    if (w.type == "segment") {
      w.from = read_vector(t, "from", zero, D);
      w.to = read_vector(t, "to", zero, D);
    } else {
      w.points = t.number_rows("points", 2);
      if (w.points.size() < 2) t.fail("points", "a polyline needs at least 2 points");
      w.closed = t.boolean("closed", false);
    }
  }
  return w;
}

CloudSpec read_cloud(TableReader& t, const ScenePartContext& c) {
  const int D = c.dimension;
  const List zero(static_cast<std::size_t>(D), 0.0);
  CloudSpec cl;
  cl.shape = t.string("grain", D == 3 ? "sphere" : "disc");
  check_shape(t, "grain", cl.shape, *c.templates);
  cl.lo = read_vector(t, "min", zero, D);
  cl.hi = read_vector(t, "max", zero, D);
  for (std::size_t k = 0; k < static_cast<std::size_t>(D); ++k)
    if (!(cl.hi[k] > cl.lo[k])) t.fail("max", "each component must exceed the one of 'min'");
  cl.count = static_cast<std::size_t>(t.integer("count", 0, 1, 100000000));
  if (t.has("radius") == t.has("porosity"))
    t.fail("radius", "give either the mean 'radius' or the cloud 'porosity'");
  if (t.has("radius")) cl.radius = t.positive("radius", 0.0);
  if (t.has("porosity")) cl.porosity = t.in_range("porosity", 0.5, 0.3, 0.999);
  cl.fuzz = t.in_range("radius_fuzz", 0.0, 0.0, 0.95);
  cl.velocity = read_vector(t, "velocity", zero, D);
  cl.material = read_material_name(t, "material", c);
  return cl;
}

StopSpec read_stop(TableReader& t) {
  StopSpec s;
  s.unbalanced_below = t.non_negative("unbalanced_below", 0.0);
  s.kinetic_below = t.non_negative("kinetic_below", 0.0);
  s.min_time = t.non_negative("min_time", 0.0);
  return s;
}

StopSpec read_stage_stop(TableReader& t) {
  StopSpec s = read_stop(t);
  s.servo_tolerance = t.in_range("servo_tolerance", 0.01, 1e-6, 1.0);
  return s;
}

std::pair<List, List> read_box(TableReader& t, int dimension) {
  const List zero(static_cast<std::size_t>(dimension), 0.0);
  const List lo = read_vector(t, "min", zero, dimension),
             hi = read_vector(t, "max", zero, dimension);
  for (std::size_t k = 0; k < lo.size(); ++k)
    if (!(hi[k] > lo[k])) t.fail("max", "each component must exceed the one of 'min'");
  return {lo, hi};
}

}  // namespace geodem
