#include "lab/pullout_settings.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "io/output_files.hpp"
#include "io/progress.hpp"
#include "lab/anchorage.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

PulloutSettings read_pullout(const toml::table& root, const std::string& file) {
  PulloutSettings s;
  s.file = file;
  TableReader r(root, "", file, &s.resolved);
  r.choice("kind", "pullout", {"pullout"});
  r.integer("dimension", 2, 2, 2);
  s.seed = static_cast<std::uint64_t>(r.integer("seed", 1, 0, (1LL << 62)));
  s.seeds = static_cast<int>(r.integer("seeds", 1, 1, 10000));
  r.string("title", "");

  if (auto b = r.table("box")) {
    s.box_length = b->positive("length", s.box_length);
    s.foundation = b->positive("foundation", s.foundation);
    b->finish();
  }

  read_deposited_soil(r, s);

  auto a = r.table("anchor");
  if (!a) r.fail("anchor", "missing [anchor] table (shape, runout_length, cover)");
  auto& g = s.anchor;
  g.shape = a->choice("shape", "runout", {"runout", "L", "V"});
  g.runout_length = a->positive("runout_length", g.runout_length);
  g.cover = a->positive("cover", g.cover);
  if (g.cover < 2.0 * s.radius)
    a->fail("cover", "expected at least one grain diameter (2 x soil.radius) of cover");
  g.free_length = a->positive("free_length", 4.0 * s.radius);
  g.front = a->choice("front", "wall", {"wall", "free"});
  if (g.shape != "runout") {
    g.trench_depth = a->positive("trench_depth", 0.5 * s.foundation);
    if (g.trench_depth >= s.foundation)
      a->fail("trench_depth", "the trench must be shallower than box.foundation");
    const bool width_given = a->has("trench_width");
    g.trench_width =
        a->positive("trench_width", g.shape == "V" ? 2.0 * g.trench_depth : 0.5 * g.trench_depth);
    // The trench is filled by layers dropped into it: it must be wider than the largest
    // grain (a two-disc clump spans about 4 radii).
    const double grain = 2.0 * s.radius * (1.0 + s.radius_fuzz) * (s.grains.round_only() ? 1 : 2);
    if (g.trench_width < grain)
      a->fail("trench_width",
              (width_given ? std::string("is")
                           : "defaults to " + std::string(g.shape == "V" ? "2" : "0.5") +
                                 " x trench_depth =") +
                  " " + format_number(g.trench_width) + " m, narrower than the largest grain (" +
                  format_number(grain) +
                  " m): the trench cannot be filled; widen it or use smaller grains");
  }
  if (g.shape != "runout") {
    g.edge_radius = a->non_negative("edge_radius", 0.0);
    // The arc must leave some of both straight parts.
    const auto corners = sheet_corners(g, 0.0);
    const auto bend = sheet_bend(g, 0.0);
    const double reach = (bend->start - bend->corner).norm();
    const double side = (corners[2] - corners[1]).norm();
    if (reach >= std::min(g.runout_length, side))
      a->fail("edge_radius", "the rounded edge reaches " + format_sig(reach) +
                                 " m along each part: expected less than the run-out (" +
                                 format_number(g.runout_length) + " m) and the trench side (" +
                                 format_number(side) + " m)");
  }
  const double end_x = g.runout_length + g.trench_width;
  if (end_x >= s.box_length)
    a->fail(g.shape == "runout" ? "runout_length" : "trench_width",
            "the anchor must end inside the box (runout_length + trench_width < box.length)");
  a->finish();

  read_sheet(r, s.radius, s);
  if (auto q = r.table("surcharge")) {
    s.surcharge = q->non_negative("pressure", 0.0);
    q->finish();
  }
  auto p = r.table("pull");
  if (!p) r.fail("pull", "missing [pull] table (rate, max_displacement)");
  s.rate = p->in_range("rate", s.rate, 1e-6, 10.0);
  s.max_displacement = p->positive("max_displacement", s.max_displacement);
  s.pull_damping = p->in_range("damping", s.pull_damping, 0.0, 0.99);
  s.history_points = static_cast<int>(p->integer("history_points", 200, 10, 1000000));
  s.profiles_at = p->numbers(
      "profiles_at", {0.1 * s.max_displacement, 0.3 * s.max_displacement, s.max_displacement}, 0);
  for (double d : s.profiles_at)
    if (!(d > 0.0 && d <= s.max_displacement))
      p->fail("profiles_at", "displacements must lie in (0, max_displacement]");
  p->finish();
  if (auto an = r.table("analytic")) {
    s.soil_friction_deg = an->in_range("soil_friction_deg", s.soil_friction_deg, 0.0, 89.0);
    s.soil_cohesion = an->non_negative("soil_cohesion", 0.0);
    if (an->has("interface_friction_deg"))
      s.interface_macro_friction_deg = an->in_range("interface_friction_deg", 34.0, 0.0, 89.0);
    s.interface_adhesion = an->non_negative("interface_adhesion", 0.0);
    if (an->has("earth_pressure_coefficient")) {
      double k = 0.5;
      const auto mode = an->number_or_string("earth_pressure_coefficient", k, "jaky");
      if (mode && *mode != "measured" && *mode != "jaky")
        an->fail("earth_pressure_coefficient",
                 "expected a number, \"jaky\" (1 - sin(soil_friction_deg)) or \"measured\"");
      if (!mode && !(k >= 0.0 && k <= 10.0))
        an->fail("earth_pressure_coefficient", "expected a coefficient from 0 to 10");
      if (!mode) s.earth_pressure_coefficient = k;
      s.earth_pressure_measured = mode && *mode == "measured";
    }
    an->finish();
  }
  read_deposit_time(r, s);
  if (auto o = r.table("output")) {
    s.vtk = o->boolean("vtk", true);
    s.vtk_contacts = o->boolean("vtk_contacts", false);
    s.plots = o->boolean("plots", true);
    s.columns = static_cast<int>(o->integer("columns", 24, 1, 10000));
    o->finish();
  }
  if (auto f = r.table("refinement")) {
    s.radius_factors = f->numbers("radius_factors", {1.0, 1.0 / std::sqrt(2.0), 0.5}, 2);
    for (double x : s.radius_factors)
      if (!(x > 0.05 && x <= 20.0))
        f->fail("radius_factors", "expected grain size factors in (0.05, 20]");
    f->finish();
  }
  if (auto t = r.table("checkpoint")) {
    s.checkpoint = read_checkpoint_spec(*t);
    t->finish();
  }
  r.finish();
  return s;
}

}  // namespace geodem
