#include "lab/triaxial_settings.hpp"

#include <cmath>
#include <numbers>

#include "io/output_files.hpp"
#include "scene/grain_spec_reader.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

namespace {
double tan_deg(double deg) {
  return std::tan(deg * std::numbers::pi / 180.0);
}

// [shear]: the compression tests of the triaxial kind.
void read_shear(TableReader& r, TriaxialSettings& s) {
  auto sh = r.table("shear");
  if (!sh)
    r.fail("shear", "missing [shear] table (strain_rate, max_axial_strain, confining_stress)");
  s.strain_rate = sh->in_range("strain_rate", 0.02, 1e-9, 100.0);
  s.max_axial_strain = sh->in_range("max_axial_strain", 0.15, 1e-4, 0.6);
  s.confining_stresses = sh->numbers("confining_stress", {s.compaction_stress}, 1);
  for (double v : s.confining_stresses)
    if (!(v > 0.0)) sh->fail("confining_stress", "confining stresses must be positive (Pa)");
  s.shear_damping = sh->in_range("damping", 0.1, 0.0, 0.99);
  // The cell servo corrects a fraction of the stress error each step against the packing's
  // affine stiffness (controllers/cell_servo.hpp): a smaller fraction than the wall servo's.
  s.servo_gain = sh->in_range("servo_gain", s.periodic ? 0.1 : 0.5, 1e-3, 1.0);
  s.undrained = sh->choice("drainage", "drained", {"drained", "undrained"}) == "undrained";
  s.consolidation_max_steps =
      static_cast<std::uint64_t>(sh->integer("consolidation_max_steps", 100'000, 1, (1LL << 50)));
  s.history_points = static_cast<int>(sh->integer("history_points", 300, 10, 1000000));
  s.vtk_at_strains = sh->numbers("vtk_at_strains", {}, 0);
  sh->finish();
}

}  // namespace

TriaxialSettings read_triaxial(const toml::table& root, const std::string& file) {
  TriaxialSettings s;
  s.file = file;
  TableReader r(root, "", file, &s.resolved);
  const std::string kind = r.choice(
      "kind", "triaxial",
      {"triaxial", "isotropic", "oedometer", "simple_shear", "cyclic_triaxial", "direct_shear"});
  for (LabKind k : {LabKind::kTriaxial, LabKind::kIsotropic, LabKind::kOedometer,
                    LabKind::kSimpleShear, LabKind::kCyclicTriaxial, LabKind::kDirectShear})
    if (kind == lab_kind_name(k)) s.kind = k;
  s.dimension = static_cast<int>(r.integer("dimension", 3, 2, 3));
  s.seed = static_cast<std::uint64_t>(r.integer("seed", 1, 0, (1LL << 62)));
  r.string("title", "");
  const std::size_t D = static_cast<std::size_t>(s.dimension);

  auto sample = r.table("sample");
  if (!sample) r.fail("sample", "missing [sample] table (box, count)");
  s.box = sample->numbers("box", std::vector<double>(D, 1.0), D);
  if (s.box.size() != D) sample->fail("box", "expected " + std::to_string(D) + " sizes (m)");
  for (double b : s.box)
    if (!(b > 0.0)) sample->fail("box", "sizes must be positive");
  s.periodic = sample->choice("boundary", "walls", {"walls", "periodic"}) == "periodic";
  s.count = static_cast<std::size_t>(sample->integer("count", 1000, 2, 50'000'000));
  s.radius_fuzz = sample->in_range("radius_fuzz", 0.3333, 0.0, 0.95);
  s.initial_porosity = sample->in_range("initial_porosity", 0.95, 0.5, 0.999);
  s.grains = read_grain_spec(*sample, s.dimension, read_templates(r, s.dimension));
  sample->finish();

  auto mat = r.table("material");
  if (!mat)
    r.fail("material", "missing [material] table (density, young, kt_over_kn, friction_deg)");
  s.grain = read_material(*mat, "grain");
  if (s.grain.law != LawKind::kLinear || s.grain.kn > 0.0)
    mat->fail("law", "lab tests use the linear law with a contact modulus ('young')");
  mat->finish();
  s.wall = s.grain;
  s.wall.name = "walls";
  // Lab walls are smooth and inert: no rolling resistance, no cohesion.
  s.wall.rolling_friction = s.wall.twisting_friction = 0.0;
  s.wall.normal_cohesion = s.wall.shear_cohesion = 0.0;
  {
    const bool cohesive = s.grain.normal_cohesion > 0.0 || s.grain.shear_cohesion > 0.0;
    auto b = r.table("bonds");
    TableReader* bt = b ? &*b : nullptr;
    const std::string fallback = cohesive ? "after_compaction" : "none";
    s.bonds_create =
        bt ? bt->choice("create", fallback, {"none", "after_compaction", "before_shear"})
           : fallback;
    if (bt) {
      s.bond_gap_tolerance = bt->in_range("gap_tolerance", 0.0, 0.0, 0.5);
      if (s.bonds_create != "none" && !cohesive)
        bt->fail("create", "bonds need material.normal_cohesion or material.shear_cohesion > 0");
      bt->finish();
    }
    s.resolved["bonds"]["create"] = s.bonds_create;
  }
  if (auto w = r.table("walls")) {
    s.wall.friction = tan_deg(w->in_range("friction_deg", 0.0, 0.0, 89.0));
    w->finish();
  } else {
    s.wall.friction = 0.0;
  }

  if (auto t = r.table("time")) {
    s.dt_safety = t->in_range("safety", 0.8, 1e-3, 1.0);
    s.dt_update_interval = static_cast<int>(t->integer("update_interval", 10, 1, 100000));
    t->finish();
  }

  auto c = r.table("compaction");
  if (!c) r.fail("compaction", "missing [compaction] table (confining_stress)");
  s.compaction_stress = c->positive("confining_stress", 1e4);
  if (c->has("target_porosity"))
    s.target_porosity = c->in_range("target_porosity", 0.4, 0.05, 0.95);
  s.compaction_damping = c->in_range("damping", 0.2, 0.0, 0.99);
  // Defaults derived from the stiffness: a message on them names the key they come from.
  const bool max_given = c->has("max_multiplier"), final_given = c->has("final_max_multiplier");
  s.max_multiplier = c->number("max_multiplier", 1.0 + 2e4 / s.grain.young);
  s.final_max_multiplier = c->number("final_max_multiplier", 1.0 + 2e3 / s.grain.young);
  const std::string young = format_number(s.grain.young);
  if (!(s.max_multiplier > 1.0 && s.max_multiplier < 1.5))
    c->fail("max_multiplier",
            max_given ? "expected a growth factor in (1, 1.5)"
                      : "defaults to 1 + 2e4 / material.young = 1 + 2e4 / " + young + " = " +
                            format_number(s.max_multiplier) +
                            ", not a growth factor in (1, 1.5): material.young is too low for "
                            "radius growth (give a stiffer material, or "
                            "compaction.max_multiplier)");
  if (!(s.final_max_multiplier > 1.0 && s.final_max_multiplier <= s.max_multiplier))
    c->fail("final_max_multiplier", final_given
                                        ? "expected a growth factor in (1, max_multiplier]"
                                        : "defaults to 1 + 2e3 / material.young = " +
                                              format_number(s.final_max_multiplier) +
                                              ", not a growth factor in (1, max_multiplier = " +
                                              format_number(s.max_multiplier) + "]");
  s.stress_tolerance = c->in_range("stress_tolerance", 0.005, 1e-5, 0.2);
  s.unbalanced_tolerance = c->in_range("unbalanced_tolerance", 1e-3, 1e-6, 0.5);
  s.friction_factor = c->in_range("friction_factor", 0.95, 0.1, 0.999);
  s.friction_interval = static_cast<int>(c->integer("friction_interval", 500, 1, 1000000));
  s.max_compaction_steps =
      static_cast<std::uint64_t>(c->integer("max_steps", 2'000'000, 1, (1LL << 50)));
  c->finish();

  if (s.kind != LabKind::kTriaxial) {
    auto l = r.table("loading");
    if (!l) r.fail("loading", "missing [loading] table (the " + kind + " test's program)");
    read_loading(*l, s);
    l->finish();
    if (s.kind == LabKind::kSimpleShear && !s.periodic)
      sample->fail("boundary", "simple_shear runs in a periodic cell: boundary = \"periodic\"");
    if (s.kind == LabKind::kDirectShear && s.periodic)
      sample->fail("boundary", "direct_shear runs in a box of walls: boundary = \"walls\"");
  } else {
    read_shear(r, s);
  }

  if (auto o = r.table("output")) {
    s.vtk = o->boolean("vtk", true);
    s.vtk_contacts = o->boolean("vtk_contacts", false);
    s.plots = o->boolean("plots", true);
    o->finish();
  }
  if (auto t = r.table("checkpoint")) {
    s.checkpoint = read_checkpoint_spec(*t);
    t->finish();
  }
  r.finish();
  return s;
}

}  // namespace geodem
