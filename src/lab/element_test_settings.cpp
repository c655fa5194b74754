#include "lab/element_test_settings.hpp"

#include "io/output_files.hpp"
#include "io/toml_reader.hpp"
#include "lab/triaxial_settings.hpp"

namespace geodem {

const char* lab_kind_name(LabKind k) {
  switch (k) {
    case LabKind::kTriaxial:
      return "triaxial";
    case LabKind::kIsotropic:
      return "isotropic";
    case LabKind::kOedometer:
      return "oedometer";
    case LabKind::kSimpleShear:
      return "simple_shear";
    case LabKind::kCyclicTriaxial:
      return "cyclic_triaxial";
    case LabKind::kDirectShear:
      return "direct_shear";
  }
  return "triaxial";
}

namespace {

// A list of stress steps: two or more positive stresses (Pa).
std::vector<double> read_stress_steps(TableReader& l) {
  if (!l.has("stresses"))
    l.fail("stresses", "missing: the stresses of the loading and unloading steps (Pa), in order");
  const auto v = l.numbers("stresses", {}, 2);
  for (double x : v)
    if (!(x > 0.0)) l.fail("stresses", "stresses must be positive (Pa)");
  return v;
}

}  // namespace

void read_loading(TableReader& l, TriaxialSettings& s) {
  ElementTestSettings& e = s.element;
  // The rate of the strain-controlled axes, and the cell servo's speed limit (5 times it).
  s.strain_rate = l.in_range("strain_rate", 0.02, 1e-9, 100.0);
  s.shear_damping = l.in_range("damping", 0.1, 0.0, 0.99);
  s.servo_gain = l.in_range("servo_gain", s.periodic ? 0.1 : 0.5, 1e-3, 1.0);
  s.consolidation_max_steps =
      static_cast<std::uint64_t>(l.integer("consolidation_max_steps", 100'000, 1, (1LL << 50)));
  s.confining_stresses = {s.compaction_stress};
  switch (s.kind) {
    case LabKind::kIsotropic:
    case LabKind::kOedometer:
      e.stresses = read_stress_steps(l);
      s.stage_max_steps =
          static_cast<std::uint64_t>(l.integer("stage_max_steps", 200'000, 1, (1LL << 50)));
      break;
    case LabKind::kSimpleShear:
    case LabKind::kDirectShear:
      s.confining_stresses = l.numbers("normal_stress", {s.compaction_stress}, 1);
      for (double v : s.confining_stresses)
        if (!(v > 0.0)) l.fail("normal_stress", "normal stresses must be positive (Pa)");
      s.history_points = static_cast<int>(l.integer("history_points", 300, 10, 1000000));
      if (s.kind == LabKind::kDirectShear) {
        const double length = s.box.front(), height = s.box.back();
        e.shear_velocity = l.positive("shear_velocity", 0.02 * height);
        e.max_displacement = l.in_range("max_displacement", 0.1 * length, 1e-9, 0.5 * length);
        e.frame_gap = l.in_range("frame_gap", 0.0, 0.0, 0.1 * height);
        break;
      }
      e.constant_volume = l.choice("control", "constant_stress",
                                   {"constant_stress", "constant_volume"}) == "constant_volume";
      e.shear_rate = l.in_range("shear_rate", 0.02, 1e-9, 100.0);
      e.max_shear_strain = l.in_range("max_shear_strain", 0.3, 1e-4, 2.0);
      break;
    case LabKind::kCyclicTriaxial: {
      s.confining_stresses = {l.positive("confining_stress", s.compaction_stress)};
      e.stress_cycles = l.choice("control", "strain", {"strain", "stress"}) == "stress";
      if (!l.has("amplitudes"))
        l.fail("amplitudes",
               e.stress_cycles ? "missing: the single amplitudes of the deviator q (Pa), increasing"
                               : "missing: the single amplitudes of axial strain, increasing");
      e.amplitudes = l.numbers("amplitudes", {}, 1);
      // A stress amplitude stays below the confining stress: the axial stress stays positive.
      const double top = e.stress_cycles ? s.confining_stresses[0] : 0.05;
      double last = 0.0;
      for (double a : e.amplitudes) {
        if (!(a > last && (e.stress_cycles ? a < top : a <= top)))
          l.fail("amplitudes", e.stress_cycles
                                   ? "expected increasing amplitudes of q (Pa) in (0, " +
                                         format_number(top) + "), below the confining stress"
                                   : "expected increasing amplitudes of axial strain in (0, 0.05]");
        last = a;
      }
      if (e.stress_cycles) e.failure_strain = l.in_range("failure_strain", 0.05, 1e-4, 0.3);
      e.cycles = static_cast<int>(l.integer("cycles", 2, 1, 1000));
      e.steps_per_cycle = static_cast<int>(l.integer("steps_per_cycle", 2000, 40, 100'000'000));
      e.points_per_cycle = static_cast<int>(l.integer("points_per_cycle", 200, 8, 100000));
      break;
    }
    case LabKind::kTriaxial:
      break;
  }
}

}  // namespace geodem
