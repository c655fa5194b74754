#include "lab/deposit_settings.hpp"

#include "scene/grain_spec_reader.hpp"
#include "scene/scene_settings.hpp"

namespace geodem {

void read_deposited_soil(TableReader& r, DepositedSoil& s) {
  auto soil = r.table("soil");
  if (!soil) r.fail("soil", "missing [soil] table (density, young, friction_deg, radius)");
  s.soil = read_material(*soil, "soil");
  if (s.soil.law != LawKind::kLinear || s.soil.kn > 0.0)
    soil->fail("law", "this test uses the linear law with a contact modulus ('young')");
  s.radius = soil->positive("radius", s.radius);
  s.radius_fuzz = soil->in_range("radius_fuzz", s.radius_fuzz, 0.0, 0.9);
  s.grains = read_grain_spec(*soil, 2, read_templates(r, 2));
  s.layer_thickness = soil->positive("layer_thickness", s.layer_thickness);
  s.settle_unbalanced = soil->in_range("settle_unbalanced", s.settle_unbalanced, 1e-5, 0.5);
  s.deposit_damping = soil->in_range("deposit_damping", s.deposit_damping, 0.0, 0.99);
  if (soil->has("deposit_friction_deg"))
    s.deposit_friction_deg = soil->in_range("deposit_friction_deg", 0.0, 0.0, 89.0);
  const bool cohesive = s.soil.normal_cohesion > 0.0 || s.soil.shear_cohesion > 0.0;
  s.bonds = soil->boolean("bonds", cohesive);
  if (s.bonds && !cohesive)
    soil->fail("bonds", "bonds need soil.normal_cohesion or soil.shear_cohesion > 0");
  s.bond_gap_tolerance = soil->in_range("bond_gap_tolerance", 0.0, 0.0, 0.5);
  s.deposit_cache = soil->string("deposit_cache", "");
  soil->finish();
  s.wall = s.soil;
  s.wall.name = "walls";
  s.wall.friction = 0.0;  // smooth, inert boundaries
  s.wall.rolling_friction = s.wall.twisting_friction = 0.0;
  s.wall.normal_cohesion = s.wall.shear_cohesion = 0.0;
}

void read_sheet(TableReader& r, double radius, SheetSettings& s) {
  s.element_length = 2.0 * radius;
  s.thickness = 0.2 * radius;
  auto sh = r.table("sheet");
  if (!sh) return;
  s.stiffness_J = sh->positive("stiffness_J", s.stiffness_J);
  s.element_length = sh->positive("element_length", s.element_length);
  s.interface_friction_deg = sh->in_range("interface_friction_deg", 34.0, 0.0, 89.0);
  s.mass_per_area = sh->positive("mass_per_area", s.mass_per_area);
  s.thickness = sh->positive("thickness", s.thickness);
  s.bending = sh->non_negative("bending_stiffness", 0.0);
  s.rest_flat = sh->choice("rest_shape", "flat", {"flat", "as_laid"}) == "flat";
  s.mass_scaling = sh->boolean("mass_scaling", true);
  s.node_mass_factor = sh->non_negative("node_mass_factor", 0.0);
  if (s.node_mass_factor > 0.0 && s.node_mass_factor < 1.0)
    sh->fail("node_mass_factor", "a factor of 1 or more (0: the automatic estimate)");
  if (s.node_mass_factor > 0.0 && !s.mass_scaling)
    sh->fail("node_mass_factor", "no factor with mass_scaling = false (the true mass)");
  sh->finish();
}

void read_deposit_time(TableReader& r, DepositTime& s) {
  auto t = r.table("time");
  if (!t) return;
  s.dt_safety = t->in_range("safety", s.dt_safety, 1e-3, 1.0);
  s.dt_update_interval = static_cast<int>(t->integer("update_interval", 20, 1, 100000));
  s.max_settle_steps =
      static_cast<std::uint64_t>(t->integer("max_settle_steps", 400'000, 100, (1LL << 50)));
  t->finish();
}

}  // namespace geodem
