#include "lab/interface_shear_settings.hpp"

namespace geodem {

InterfaceShearSettings read_interface_shear(const toml::table& root, const std::string& file) {
  InterfaceShearSettings s;
  s.file = file;
  TableReader r(root, "", file, &s.resolved);
  r.choice("kind", "interface_shear", {"interface_shear"});
  r.integer("dimension", 2, 2, 2);
  s.seed = static_cast<std::uint64_t>(r.integer("seed", 1, 0, (1LL << 62)));
  r.string("title", "");

  if (auto b = r.table("box")) {
    s.box_length = b->positive("length", s.box_length);
    s.box_height = b->positive("height", s.box_height);
    s.base = b->choice("base", s.base, {"rigid", "soil"});
    // Read whatever the base, so that one file serves both (--set box.base=...).
    s.lower_height = b->positive("lower_height", s.box_height);
    b->finish();
  }
  read_deposited_soil(r, s);
  if (s.base == "soil" && s.lower_height < 6.0 * s.radius)
    r.fail("box",
           "the soil under the sheet must be at least 3 grains' diameters thick "
           "(box.lower_height >= 6 x soil.radius)");
  if (s.box_height < 6.0 * s.radius || s.box_length < 10.0 * s.radius)
    r.fail("box",
           "the box must hold at least 3 grains' diameters of soil (box.height >= 6 x "
           "soil.radius) and 5 along the sheet (box.length >= 10 x soil.radius)");
  read_sheet(r, s.radius, s);

  auto sh = r.table("shear");
  if (!sh) r.fail("shear", "missing [shear] table (normal_stress, rate, max_displacement)");
  s.normal_stress = sh->numbers("normal_stress", s.normal_stress, 1);
  for (double x : s.normal_stress)
    if (!(x > 0.0)) sh->fail("normal_stress", "expected normal stresses > 0 (Pa)");
  s.rate = sh->in_range("rate", s.rate, 1e-6, 10.0);
  s.max_displacement = sh->positive("max_displacement", s.max_displacement);
  if (s.max_displacement > (s.base == "soil" ? 0.5 : 1.0) * s.box_length)
    sh->fail("max_displacement", s.base == "soil"
                                     ? "expected at most half box.length of pull (the sheet "
                                       "must stay embedded)"
                                     : "expected at most box.length of slip");
  s.damping = sh->in_range("damping", s.damping, 0.0, 0.99);
  s.normal_stiffness = sh->non_negative("normal_stiffness", 0.0);
  s.residual_from = sh->in_range("residual_from", s.residual_from, 0.0, 0.99);
  s.consolidation_tolerance =
      sh->in_range("consolidation_tolerance", s.consolidation_tolerance, 1e-4, 0.5);
  s.history_points = static_cast<int>(sh->integer("history_points", 200, 10, 1000000));
  sh->finish();
  read_deposit_time(r, s);
  if (auto o = r.table("output")) {
    s.vtk = o->boolean("vtk", true);
    s.vtk_contacts = o->boolean("vtk_contacts", false);
    s.plots = o->boolean("plots", true);
    o->finish();
  }
  r.finish();
  return s;
}

}  // namespace geodem
