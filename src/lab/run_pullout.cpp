// The pull-out test of a geosynthetic anchorage (docs/lab_tests.md, "Pull-out"):
//   1. foundation: gravity deposition in layers in a rigid box, trimmed flat at the
//      run-out level; the trench (L or V) is excavated;
//   2. the sheet is laid along the anchor's shape; the foundation is held still while
//      the trench and the cover are filled by deposition in layers and trimmed flat;
//   3. optional surcharge plate; the foundation is released and everything settles;
//      cohesive soils are bonded;
//   4. the free end is pulled horizontally at a constant rate; the tension there, the
//      tension profile and the displacement of the anchoring soil are recorded.
#include "lab/run_pullout.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "contacts/bonds.hpp"
#include "controllers/surface_pressure.hpp"
#include "core/error.hpp"
#include "core/random.hpp"
#include "core/step.hpp"
#include "integrate/critical_timestep.hpp"
#include "io/interrupt.hpp"
#include "io/output_files.hpp"
#include "io/progress.hpp"
#include "lab/anchorage.hpp"
#include "lab/soil_editing.hpp"
#include "measure/measurements.hpp"

namespace geodem {

namespace {

using Vec = Dim<2>::Vec;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kGravity = 9.81;
// Layer sizes: a dense 2D packing's porosity guess, and the fraction of its height the
// bounding discs of a loose cloud fill (random sequential addition jams near 0.5 in 2D).
constexpr double kDensePorosity = 0.16, kLooseFill = 0.3;
enum : std::uint16_t { kSoil = 0, kWalls = 1, kSheet = 2 };
constexpr std::size_t kFrontWall = 1;  // index in World::walls (floor, front, back)

struct Pullout {
  const PulloutSettings& s;
  const RunOptions& opt;
  World<2> w;
  Progress progress;
  Random rng;
  std::vector<ResolvedKind<2>> kinds;
  double mean_grain_area = 0.0;
  double bound_ratio = 1.0;  // area of the grains' bounding discs over their own area
  double y0 = 0.0;           // run-out level: top of the foundation
  std::uint64_t total_steps = 0;
  HistoryCsv prep_csv;
  double node_mass_factor = 1.0;

  Pullout(const PulloutSettings& settings, const RunOptions& options)
      : s(settings), opt(options), progress(options.quiet), rng(settings.seed) {}

  void build() {
    Material sheet = s.soil;
    sheet.name = "sheet";
    sheet.friction = std::tan(s.interface_friction_deg * kDeg);
    sheet.rolling_friction = sheet.twisting_friction = 0.0;
    sheet.normal_cohesion = sheet.shear_cohesion = 0.0;
    w.materials = {s.soil, s.wall, sheet};
    auto plane = [&](const char* name, Vec point, Vec normal, double area) {
      Wall<2> wall;
      wall.name = name;
      wall.point = point;
      wall.normal = normal;
      wall.material = kWalls;
      wall.area = area;
      w.walls.push_back(wall);
    };
    plane("floor", Vec(0.0, 0.0), Vec(0.0, 1.0), s.box_length);
    plane("front", Vec(0.0, 0.0), Vec(1.0, 0.0), 0.0);
    plane("back", Vec(s.box_length, 0.0), Vec(-1.0, 0.0), 0.0);
    w.resolve_pair_laws();
    // Soil against sheet: the interface friction alone (no rolling resistance, no bond).
    for (auto* law : {&w.pair_laws[kSoil * 3 + kSheet], &w.pair_laws[kSheet * 3 + kSoil]}) {
      law->mu = std::tan(s.interface_friction_deg * kDeg);
      law->roll_mu = law->twist_mu = 0.0;
      law->bond_tension = law->bond_shear = 0.0;
    }
    w.update_contact_extras();
    if (s.deposit_friction_deg >= 0.0) set_soil_friction(std::tan(s.deposit_friction_deg * kDeg));
    w.gravity = Vec(0.0, -kGravity);
    w.auto_dt = true;
    w.dt_safety = s.dt_safety;
    w.dt_update_interval = s.dt_update_interval;
    w.sort_interval = 10;
    w.threads = opt.threads;
    w.local_damping = s.deposit_damping;
    kinds = resolve_kinds<2>(s.grains);
    double fsum = 0.0;
    for (const auto& k : kinds) fsum += k.fraction;
    const double fuzz = s.radius_fuzz;
    double bound_area = 0.0;
    for (const auto& k : kinds) {
      const double scale2 = k.size * k.size * (1.0 + fuzz * fuzz / 3.0) * s.radius * s.radius;
      mean_grain_area += k.fraction / fsum * k.clump.volume * scale2;
      bound_area += k.fraction / fsum * Dim<2>::volume(k.clump.bounding_radius) * scale2;
    }
    bound_ratio = bound_area / mean_grain_area;
    prep_csv.open(opt.out_dir + "/preparation.csv",
                  {"stage", "step", "time", "grains", "surface", "unbalanced", "kinetic_energy"});
  }

  // Sets the soil's contact friction; its rolling friction follows in proportion (none
  // while the friction is 0).
  void set_soil_friction(double mu) {
    PairLaw& law = w.pair_laws[kSoil * 3 + kSoil];
    const double ratio = s.soil.friction > 0.0 ? mu / s.soil.friction : 0.0;
    law.mu = mu;
    law.roll_mu = s.soil.rolling_friction * ratio;
    law.twist_mu = s.soil.twisting_friction * ratio;
  }

  double top_of_grains() const {
    double top = 0.0;
    for (std::size_t i = 0; i < w.particles.size(); ++i)
      top = std::max(top, w.particles.pos[i].y() + w.particles.radius[i]);
    return top;
  }
  // Median over columns of [x0, x1] of the highest grain top: the free surface's level.
  double surface(double x0, double x1) const {
    constexpr int kCols = 12;
    std::vector<double> top(kCols, 0.0);
    for (std::size_t i = 0; i < w.particles.size(); ++i) {
      const double x = w.particles.pos[i].x();
      if (x < x0 || x > x1) continue;
      const auto c = static_cast<std::size_t>(
          std::clamp(static_cast<int>((x - x0) / (x1 - x0) * kCols), 0, kCols - 1));
      top[c] = std::max(top[c], w.particles.pos[i].y() + w.particles.radius[i]);
    }
    std::nth_element(top.begin(), top.begin() + kCols / 2, top.end());
    return top[kCols / 2];
  }

  void prep_row(double stage, double unb) {
    prep_csv.row({stage, static_cast<double>(w.step), w.time,
                  static_cast<double>(w.particles.size()), surface(0.0, s.box_length), unb,
                  kinetic_energy(w)});
  }

  // Steps until the unbalanced force ratio falls below the settings' threshold.
  void settle(const std::string& stage, double stage_code) {
    const std::uint64_t every = 200;
    for (std::uint64_t k = 1;; ++k) {
      w.measure_this_step = k % every == 0;
      step(w);
      stop_if_interrupted();
      ++total_steps;
      if (!w.measure_this_step) continue;
      const double unb = unbalanced_force_ratio(w);
      progress.update(
          stage, w.step, w.time, 0.0,
          std::to_string(w.particles.size()) + " grains, unbalanced " + format_number(unb));
      if (k % (5 * every) == 0) prep_row(stage_code, unb);
      if (k >= 5 * every && unb < s.settle_unbalanced) return;
      if (k >= s.max_settle_steps)
        throw std::runtime_error(stage + ": the soil did not come to rest (unbalanced force " +
                                 format_number(unb) + " after " + std::to_string(k) +
                                 " steps); raise time.max_settle_steps or soil.settle_unbalanced");
    }
  }

  // Deposits layers over [x0, x1] until the surface there reaches `height`.
  void deposit_to(double height, double x0, double x1, const std::string& stage,
                  double stage_code) {
    int layer = 0;
    while (w.particles.size() == 0 || surface(x0, x1) < height) {
      const double base = w.particles.size() == 0 ? 0.0 : top_of_grains();
      const double from = w.particles.size() == 0 ? 0.0 : surface(x0, x1);
      const double dense = std::min(s.layer_thickness, height - from + 2.0 * s.radius);
      const auto count = static_cast<std::size_t>(
          std::ceil((1.0 - kDensePorosity) * (x1 - x0) * dense / mean_grain_area));
      const double loose = dense * (1.0 - kDensePorosity) * bound_ratio / kLooseFill;
      try {
        add_random_grains<2>(w, kinds, Vec(x0, base), Vec(x1, base + loose), count,
                             1.0 - kLooseFill, s.radius_fuzz, s.soil.density, kSoil, rng,
                             Vec::Zero(), s.radius);
      } catch (const std::runtime_error& e) {
        throw InputError(s.file, 0, "soil.layer_thickness", e.what());
      }
      w.rebuild_needed = true;
      settle(stage + " layer " + std::to_string(++layer), stage_code);
    }
  }

  std::vector<char> select(const std::function<bool(std::size_t)>& pred) const {
    std::vector<char> m(w.particles.size(), 0);
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = pred(i) ? 1 : 0;
    return m;
  }

  // Foundation, trench, sheet, fill, surcharge, bonds. Returns the preparation summary.
  nlohmann::json prepare() {
    nlohmann::json prep;
    const auto& P = w.particles;
    y0 = s.foundation;
    deposit_to(y0 + 2.0 * s.radius, 0.0, s.box_length, "foundation", 1);
    // Flat top at the run-out level, and the trench.
    const double t = s.thickness;
    remove_grains(w, select([&](std::size_t i) {
                    return P.pos[i].y() + P.radius[i] > y0 ||
                           overlaps_trench(s.anchor, y0, P.pos[i], P.radius[i] + t);
                  }));
    prep["foundation_grains"] = P.size();
    for (std::size_t i = 0; i < P.size(); ++i) w.particles.id[i] = static_cast<std::uint32_t>(i);

    // The sheet, its axis half a thickness above the foundation's top.
    const auto corners = sheet_corners(s.anchor, y0 + 0.5 * t);
    const auto nodes = sheet_nodes(corners, s.element_length);
    std::vector<Vec> pts(nodes.begin(), nodes.end());
    w.spars.add_chain("sheet", pts, s.stiffness_J, s.mass_per_area, t, kSheet, s.bending);
    w.spars.flags[0] = kNodeDriven;  // the clamp, still until the pull
    if (s.mass_scaling) scale_node_masses();
    w.rebuild_needed = true;

    // Fill the trench and the cover with the foundation held (a face that stands while
    // the trench is open), trim it flat, and release.
    const std::size_t foundation = P.size();
    const std::vector<char> found_mask(foundation, 1);
    hold_grains(w, found_mask, true);
    const double top = y0 + s.anchor.cover;
    if (s.anchor.shape != "runout")  // the trench first, then the whole cover
      deposit_to(y0, s.anchor.runout_length, s.anchor.runout_length + s.anchor.trench_width,
                 "trench fill", 2);
    deposit_to(top + 2.0 * s.radius, 0.0, s.box_length, "cover", 2);
    // Renumbering moved the held grains: find them by id (new grains have larger ids).
    auto is_foundation = [&](std::size_t i) { return P.id[i] < foundation; };
    remove_grains(w, select([&](std::size_t i) {
                    return !is_foundation(i) && P.pos[i].y() + P.radius[i] > top;
                  }));
    hold_grains(w, select(is_foundation), false);
    prep["fill_grains"] = P.size() - foundation;
    if (s.anchor.front == "free") {
      // The front wall now holds the foundation only: the cover's face is free.
      Wall<2>& front = w.walls[kFrontWall];
      front.kind = WallKind::kSegment;
      front.point = Vec(0.0, -s.radius);
      front.end = Vec(0.0, y0);
      w.rebuild_needed = true;
    }
    if (s.surcharge > 0.0) add_surcharge_plate(top);
    set_soil_friction(s.soil.friction);  // the soil's own friction from here on
    settle("consolidation", 3);
    if (s.anchor.front == "free") {
      // Grains that fell off the free face are no longer part of the anchorage.
      const std::size_t spilled =
          remove_grains(w, select([&](std::size_t i) { return P.pos[i].x() < 0.0; }));
      prep["spilled_grains"] = spilled;
      if (spilled > 0) settle("consolidation", 3);
    }
    if (s.bonds) {
      prep["bonds"] = create_bonds(w, s.bond_gap_tolerance);
      settle("bonded", 4);
    }
    prep["grains"] = P.size();
    prep["bodies"] = body_count(w);
    prep["steps"] = w.step;
    prep["time"] = w.time;
    return prep;
  }

  // Node masses raised so that the sheet's own critical step is no shorter than the
  // grains' (a quasi-static pull does not feel the sheet's inertia; docs/lab_tests.md).
  void scale_node_masses() {
    auto& S = w.spars;
    World<2> grains_only = w;
    grains_only.spars = SparChains<2>{};
    grains_only.rebuild_needed = true;
    const double dt = critical_timestep(grains_only) / w.dt_safety;
    const double m_over_k = 0.5 * dt * dt;        // dt^2 = 2 m / k
    const double k_contact = 2.0 * s.soil.young;  // a grain on each face (2D: kn = E)
    double factor = 1.0;
    for (std::size_t i = 0; i < S.nodes(); ++i) {
      const double k = 2.0 * s.stiffness_J / s.element_length + k_contact;
      factor = std::max(factor, 1.1 * k * m_over_k / S.mass[i]);
    }
    // Inertia only: gravity still acts on the sheet's true mass.
    for (std::size_t i = 0; i < S.nodes(); ++i) S.inertial_mass[i] = factor * S.mass[i];
    node_mass_factor = factor;
  }

  std::shared_ptr<SurfacePressure<2>> surcharge;
  void add_surcharge_plate(double top) {
    Wall<2> plate;
    plate.name = "surcharge";
    plate.point = Vec(0.0, top + 0.5 * s.radius);
    plate.normal = Vec(0.0, -1.0);
    plate.material = kWalls;
    plate.area = s.box_length;
    w.walls.push_back(plate);
    w.resolve_pair_laws();
    for (auto* law : {&w.pair_laws[kSoil * 3 + kSheet], &w.pair_laws[kSheet * 3 + kSoil]}) {
      law->mu = std::tan(s.interface_friction_deg * kDeg);
      law->roll_mu = law->twist_mu = 0.0;
      law->bond_tension = law->bond_shear = 0.0;
    }
    w.update_contact_extras();
    surcharge = std::make_shared<SurfacePressure<2>>(w.walls.size() - 1, s.surcharge,
                                                     0.05 * s.radius / w.dt);
    w.controllers = {surcharge};
  }
};

void write_states(const std::string& path_grains, const std::string& path_sheet, const World<2>& w,
                  const std::vector<int>& column_by_id) {
  std::filesystem::create_directories(std::filesystem::path(path_grains).parent_path());
  HistoryCsv g;
  g.open(path_grains, {"id", "x", "y", "radius", "column"});
  const auto& P = w.particles;
  for (std::size_t i = 0; i < P.size(); ++i)
    g.row({static_cast<double>(P.id[i]), P.pos[i].x(), P.pos[i].y(), P.radius[i],
           static_cast<double>(column_by_id[P.id[i]])});
  HistoryCsv sh;
  sh.open(path_sheet, {"node", "x", "y", "tension"});
  const auto& S = w.spars;
  for (std::size_t i = 0; i < S.nodes(); ++i)
    sh.row({static_cast<double>(i), S.pos[i].x(), S.pos[i].y(),
            i < S.elements() ? S.tension[i] : 0.0});
}

}  // namespace

namespace {
nlohmann::json run_pullout_test(const PulloutSettings& s, const RunOptions& opt) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  prepare_output_dir(opt.out_dir);
  Pullout run(s, opt);
  run.build();
  nlohmann::json results;
  results["preparation"] = run.prepare();
  World<2>& w = run.w;
  auto& P = w.particles;
  auto& S = w.spars;

  // The anchoring soil: the fill above the run-out and in the trench (ids of grains are
  // their indices after the preparation: no grain is added or removed from here on).
  const std::size_t n = P.size();
  for (std::size_t i = 0; i < n; ++i) P.id[i] = static_cast<std::uint32_t>(i);
  const double x_end = s.anchor.runout_length + s.anchor.trench_width;
  std::vector<char> zone(n, 0);
  std::vector<Vec> start(n);
  std::vector<int> column(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec x = P.pos[i];
    start[i] = x;
    column[i] = std::clamp(static_cast<int>(x.x() / s.box_length * s.columns), 0, s.columns - 1);
    const bool above = x.y() > run.y0;
    const bool in_trench = overlaps_trench(s.anchor, run.y0, x, 0.0);
    zone[i] = x.x() > 0.0 && x.x() < x_end && (above || in_trench) ? 1 : 0;
  }
  std::size_t zone_count = 0;
  for (char z : zone) zone_count += z;
  // Displacement of the anchoring soil towards the pull: the mean, and the median (which
  // grains that roll off a free face far from the anchor do not pull up).
  std::vector<double> moved;
  auto soil_displacement = [&](bool median = false) {
    moved.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (zone[P.id[i]]) moved.push_back(start[P.id[i]].x() - P.pos[i].x());
    if (moved.empty()) return 0.0;
    if (median) {
      std::nth_element(moved.begin(), moved.begin() + moved.size() / 2, moved.end());
      return moved[moved.size() / 2];
    }
    double sum = 0.0;
    for (double d : moved) sum += d;
    return sum / static_cast<double>(moved.size());
  };

  // Unit weight of the cover where it is whole (next to the end of the run-out): solid
  // area in the box x density x g over the box's area; and the load on the run-out: the
  // weight of the soil above it plus the surcharge, for the analytic estimate.
  const double L = s.anchor.runout_length;
  Box<2> cover{Vec(std::max(0.0, L - 2.0 * s.anchor.cover), run.y0 + s.thickness),
               Vec(L, run.y0 + s.anchor.cover)};
  const double unit_weight =
      solid_volume_in_box(w, cover) / cover.volume() * s.soil.density * kGravity;
  const double sigma_q = run.surcharge ? run.surcharge->pressure(w) : 0.0;
  double runout_load = sigma_q * L;
  for (std::size_t i = 0; i < n; ++i)
    if (P.pos[i].y() > run.y0 && P.pos[i].x() > 0.0 && P.pos[i].x() < L)
      runout_load += Dim<2>::volume(P.radius[i]) * s.soil.density * kGravity;
  const double K = s.earth_pressure_coefficient >= 0.0 ? s.earth_pressure_coefficient
                                                       : 1.0 - std::sin(s.soil_friction_deg * kDeg);
  const SlipEstimate est = slip_estimate(s.anchor, unit_weight, sigma_q,
                                         std::tan(s.interface_friction_deg * kDeg), K, runout_load);

  write_states(opt.out_dir + "/states/grains_initial.csv",
               opt.out_dir + "/states/sheet_initial.csv", w, column);
  VtkSeries<2> vtk(opt.out_dir);
  if (s.vtk) vtk.write(w);

  // The pull.
  HistoryCsv history;
  history.open(opt.out_dir + "/history.csv",
               {"step", "time", "displacement", "tension", "tension_step", "soil_displacement",
                "soil_displacement_median", "kinetic_energy", "unbalanced", "sheet_contacts"});
  HistoryCsv profiles;
  profiles.open(opt.out_dir + "/tension_profiles.csv", {"displacement", "s", "tension"});
  std::vector<double> profile_at = s.profiles_at;
  std::sort(profile_at.begin(), profile_at.end(), std::greater<>());
  w.local_damping = s.pull_damping;
  const Vec clamp0 = S.pos[0];
  S.vel[0] = Vec(-s.rate, 0.0);
  const double d_record = s.max_displacement / s.history_points;
  double next_record = d_record, tension_sum = 0.0;
  std::uint64_t tension_steps = 0;
  double t_max = 0.0, d_at_max = 0.0, soil_at_max = 0.0;
  double displacement = 0.0;
  const std::uint64_t pull_start = w.step;
  while (displacement < s.max_displacement) {
    const double next_d = clamp0.x() - (S.pos[0].x() - s.rate * w.dt);
    w.measure_this_step = next_d >= next_record || next_d >= s.max_displacement;
    step(w);
    stop_if_interrupted();
    ++run.total_steps;
    displacement = clamp0.x() - S.pos[0].x();
    tension_sum += S.tension[0];
    ++tension_steps;
    // The last row is always written, even when a change of dt made the prediction miss it.
    if (w.measure_this_step || displacement >= s.max_displacement) {
      // The tension of a row is its mean over the steps since the previous row: the
      // per-step value carries the sheet's own vibrations.
      const double T = tension_sum / static_cast<double>(tension_steps);
      const double soil = soil_displacement();
      history.row({static_cast<double>(w.step), w.time, displacement, T, S.tension[0], soil,
                   soil_displacement(true), kinetic_energy(w), unbalanced_force_ratio(w),
                   static_cast<double>(w.stats.spar_contacts)});
      if (T > t_max) t_max = T, d_at_max = displacement, soil_at_max = soil;
      tension_sum = 0.0;
      tension_steps = 0;
      while (next_record <= displacement) next_record += d_record;
      run.progress.update("pull", w.step, w.time, displacement / s.max_displacement,
                          "T " + format_number(T) + " N/m");
    }
    while (!profile_at.empty() && displacement >= profile_at.back() - 1e-12) {
      double arc = 0.0;
      for (std::size_t e = 0; e < S.elements(); ++e) {
        const double len = S.length(e);
        profiles.row({profile_at.back(), arc + 0.5 * len, S.tension[e]});
        arc += len;
      }
      if (s.vtk) vtk.write(w);
      profile_at.pop_back();
    }
  }
  run.progress.finish();
  write_states(opt.out_dir + "/states/grains_final.csv", opt.out_dir + "/states/sheet_final.csv", w,
               column);
  if (s.vtk) vtk.write(w);

  results["T_max"] = t_max;
  results["displacement_at_T_max"] = d_at_max;
  results["T_analytic_slip"] = est.tension;
  results["T_max_over_analytic"] = est.tension > 0.0 ? t_max / est.tension : 0.0;
  results["soil_displacement_mean"] = soil_displacement();
  results["soil_displacement_median"] = soil_displacement(true);
  results["soil_displacement_at_T_max"] = soil_at_max;
  results["soil_displacement_ratio"] = soil_displacement() / s.max_displacement;
  results["anchoring_zone_grains"] = zone_count;
  results["analytic"] = {{"unit_weight", unit_weight},
                         {"sigma_v0", est.sigma_v0},
                         {"surcharge_measured", sigma_q},
                         {"runout_load", runout_load},
                         {"K", est.K},
                         {"runout_friction", est.runout},
                         {"trench_friction", est.trench},
                         {"capstan_factor", est.capstan}};
  results["sheet"] = {
      {"nodes", S.nodes()}, {"elements", S.elements()}, {"node_mass_factor", run.node_mass_factor}};
  results["pull_steps"] = w.step - pull_start;
  results["dt"] = w.dt;
  results["grains"] = P.size();

  const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return write_run_summary(opt.out_dir, "pullout", "completed", s.resolved, results,
                           timing_json(w, wall_s, run.total_steps, opt.threads));
}
}  // namespace

nlohmann::json run_pullout(const PulloutSettings& s, const RunOptions& opt) {
  try {
    return run_pullout_test(s, opt);
  } catch (const Interrupted& i) {
    write_interrupted_summary(opt.out_dir, "pullout", s.resolved, i.signal, opt.threads);
    throw;
  }
}

}  // namespace geodem
