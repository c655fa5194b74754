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

ChainSpec read_chain(TableReader& t, const ScenePartContext& c, std::size_t index) {
  const auto D = static_cast<std::size_t>(c.dimension);
  ChainSpec ch;
  ch.name = t.string("name", "chain" + std::to_string(index));
  ch.material = read_material_name(t, "material", c);
  ch.points = t.number_rows("points", D);
  if (ch.points.size() < 2) t.fail("points", "a chain needs at least 2 points");
  double nodes = 1.0;
  ch.element_length = t.non_negative("element_length", 0.0);
  for (std::size_t k = 0; k + 1 < ch.points.size(); ++k) {
    double d2 = 0.0;
    for (std::size_t j = 0; j < D; ++j)
      d2 += (ch.points[k + 1][j] - ch.points[k][j]) * (ch.points[k + 1][j] - ch.points[k][j]);
    if (d2 == 0.0) t.fail("points", "two consecutive points coincide");
    if (ch.element_length > 0.0) nodes += std::ceil(std::sqrt(d2) / ch.element_length);
  }
  if (nodes > 1e7) t.fail("element_length", "more than 10 million nodes: too short");
  ch.stiffness = t.positive("stiffness_J", 1e5);
  ch.mass_per_length = t.positive("mass_per_length", 0.5);
  ch.thickness = t.non_negative("thickness", 0.0);
  ch.bending = t.non_negative("bending_stiffness", 0.0);
  if (ch.bending > 0.0 && c.dimension != 2)
    t.fail("bending_stiffness", "bending stiffness of chains is available in 2D only");
  for (double h : t.numbers("held", {}, 0)) {
    if (h != std::floor(h) || std::abs(h) > 1e9) t.fail("held", "expected node indices (integers)");
    ch.held.push_back(static_cast<long long>(h));
  }
  if (t.has("velocity") && ch.held.empty())
    t.fail("velocity", "a velocity is for held nodes: list them in 'held'");
  ch.velocity = read_vector(t, "velocity", List(D, 0.0), c.dimension);
  return ch;
}

ClumpSpec read_clump(TableReader& t, const ScenePartContext& c) {
  const int D = c.dimension;
  ClumpSpec cl;
  cl.shape = t.string("template", "");
  if (cl.shape.empty()) t.fail("template", "missing; expected a clump template name");
  check_shape(t, "template", cl.shape, *c.templates);
  cl.position = read_vector(t, "position", List(static_cast<std::size_t>(D), 0.0), D);
  cl.velocity = read_vector(t, "velocity", List(static_cast<std::size_t>(D), 0.0), D);
  cl.scale = t.positive("scale", 1.0);
  cl.angle_deg = t.number("angle_deg", 0.0);
  cl.axis = D == 3 ? read_vector(t, "axis", List{0.0, 0.0, 1.0}, D) : List{};
  if (D == 3 && cl.axis[0] == 0.0 && cl.axis[1] == 0.0 && cl.axis[2] == 0.0)
    t.fail("axis", "expected a non-zero rotation axis");
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
