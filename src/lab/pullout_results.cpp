#include "lab/pullout_results.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "io/output_files.hpp"
#include "lab/anchorage_mechanism.hpp"
#include "measure/measurements.hpp"

namespace geodem {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kGravity = 9.81;
constexpr std::size_t kBackWall = 2;  // in World::walls (floor, front, back)
// A row of the sheet's parts: per part the tension it took off the sheet, the grains'
// normal force on it and their ratio (the bend: the tension ratio across it).
nlohmann::json sheet_parts_json(const SheetPartLoads& p) {
  auto part = [&](std::size_t k) {
    return nlohmann::json{
        {"carried", p.carried[k]}, {"normal", p.normal[k]}, {"mobilised", p.mobilised(k)}};
  };
  nlohmann::json bend = part(kBendPart);
  bend["tension_ratio"] = p.bend_ratio();
  return {{"runout", part(kRunoutPart)}, {"bend", bend}, {"trench", part(kTrenchPart)}};
}

// The same terms as the slippage estimate assumes them: F1 on the run-out's at-rest load,
// the capstan factor at the bend, F2 on the trench part's at-rest normal force.
nlohmann::json estimate_parts_json(const AnchorEstimate& e) {
  auto ratio = [](double a, double b) { return b > 0.0 ? a / b : 0.0; };
  return {{"runout",
           {{"carried", e.runout},
            {"normal", e.runout_normal},
            {"mobilised", ratio(e.runout, e.runout_normal)}}},
          {"bend", {{"carried", (e.capstan - 1.0) * e.trench}, {"tension_ratio", e.capstan}}},
          {"trench",
           {{"carried", e.trench},
            {"normal", e.trench_normal},
            {"mobilised", ratio(e.trench, e.trench_normal)}}}};
}

}  // namespace

void start_pull(Pull& u, const World<2>& w, const Particles<2>& P, const PulloutSettings& s,
                double y0, double top, double sigma_q) {
  using Vec = Dim<2>::Vec;
  const std::size_t n = P.size();
  std::size_t ids = 0;  // (the arrays by id: as many as the largest id and one)
  for (std::size_t i = 0; i < n; ++i) ids = std::max<std::size_t>(ids, P.id[i] + std::size_t{1});
  const double x_end = s.anchor.runout_length + s.anchor.trench_width;
  u.zone.assign(ids, 0);
  u.start.assign(ids, Vec::Zero());
  u.column.assign(ids, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec x = P.pos[i];
    const std::uint32_t id = P.id[i];
    u.start[id] = x;
    u.column[id] = std::clamp(static_cast<int>(x.x() / s.box_length * s.columns), 0, s.columns - 1);
    const bool above = x.y() > y0;
    const bool in_trench = overlaps_trench(s.anchor, y0, x, 0.0);
    u.zone[id] = x.x() > 0.0 && x.x() < x_end && (above || in_trench) ? 1 : 0;
  }
  u.zone_count = 0;
  for (char z : u.zone) u.zone_count += static_cast<std::uint64_t>(z);

  // Unit weight of the cover where it is whole (next to the end of the run-out): solid
  // area in the box x density x g over the box's area; and the load on the run-out: the
  // weight of the soil above it plus the surcharge, for the analytic estimate.
  const double L = s.anchor.runout_length;
  Box<2> cover{Vec(std::max(0.0, L - 2.0 * s.anchor.cover), y0 + s.thickness),
               Vec(L, y0 + s.anchor.cover)};
  u.unit_weight = solid_volume_in_box(w, cover) / cover.volume() * s.soil.density * kGravity;
  u.sigma_q = sigma_q;
  u.runout_load = u.sigma_q * L;
  for (std::size_t i = 0; i < n; ++i)
    if (P.pos[i].y() > y0 && P.pos[i].x() > 0.0 && P.pos[i].x() < L)
      u.runout_load += Dim<2>::volume(P.radius[i]) * s.soil.density * kGravity;
  // The lateral stress the soil holds: on the smooth back wall, whose force balances
  // K (q H + gamma H^2 / 2) over the soil's height H there.
  const double H = top;
  u.K_jaky = 1.0 - std::sin(s.soil_friction_deg * kDeg);
  u.K_wall = w.walls[kBackWall].force.x() / (u.sigma_q * H + 0.5 * u.unit_weight * H * H);
  const double K = s.earth_pressure_measured             ? u.K_wall
                   : s.earth_pressure_coefficient >= 0.0 ? s.earth_pressure_coefficient
                                                         : u.K_jaky;
  u.est =
      slip_estimate(s.anchor, u.unit_weight, u.sigma_q, std::tan(s.macro_interface_deg() * kDeg), K,
                    u.runout_load, s.interface_adhesion);
  u.est_soil =
      soil_estimate(s.anchor, u.unit_weight, u.sigma_q, std::tan(s.soil_friction_deg * kDeg),
                    s.soil_cohesion, K, u.runout_load);
  // Next to the sheet: within a grain diameter of its faces.
  const std::vector<char> near = grains_near_sheet(P, w.spars, 2.0 * s.radius + 0.5 * s.thickness);
  u.near.assign(ids, 0);
  for (std::size_t i = 0; i < n; ++i) u.near[P.id[i]] = near[i] && P.pos[i].x() > 0.0 ? 1 : 0;
  u.node_start = w.spars.pos;
  // The pull's own counters: records, profiles (taken from the back), the largest tension.
  u.profile_at = s.profiles_at;
  std::sort(u.profile_at.begin(), u.profile_at.end(), std::greater<>());
  u.clamp0 = w.spars.pos[0];
  u.next_record = s.max_displacement / s.history_points;
  u.tension_sum = 0.0;
  u.tension_steps = 0;
  u.t_max = u.d_at_max = u.soil_at_max = u.displacement = 0.0;
  u.soil_median_at_max = u.near_at_max = u.nodes_at_max = 0.0;
  u.late_sum = 0.0, u.late_rows = 0;
  u.pull_start = w.step;
  // The bend: where an L or V turns from the run-out (the middle of the arc round a
  // rounded trench edge, with the band reaching both its ends).
  const auto bend = sheet_bend(s.anchor, y0 + 0.5 * s.thickness);
  u.has_corner = bend ? 1 : 0;
  u.corner = bend ? bend->middle : Vec::Zero();
  u.corner_band = std::max(2.0 * s.radius, s.element_length);
  if (bend)
    u.corner_band = std::max(
        u.corner_band, 2.0 * bend->radius * std::sin(0.25 * bend->turn) + 0.5 * s.element_length);
  u.parts_sum = u.parts_first = u.parts_at_max = SheetPartLoads{};
  u.parts_first_set = 0;
}

double anchoring_soil_displacement(const Pull& u, const Particles<2>& P, bool median,
                                   std::vector<double>& scratch) {
  scratch.clear();
  for (std::size_t i = 0; i < P.size(); ++i)
    if (u.zone[P.id[i]]) scratch.push_back(u.start[P.id[i]].x() - P.pos[i].x());
  return median ? median_of(scratch) : mean_of(scratch);
}

double mean_of(const std::vector<double>& v) {
  double sum = 0.0;
  for (double d : v) sum += d;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

double median_of(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

void pull_results(const Pull& u, const World<2>& w, const Particles<2>& P, const PulloutSettings& s,
                  nlohmann::json& results) {
  std::vector<double> scratch;
  const double soil_mean = anchoring_soil_displacement(u, P, false, scratch);
  results["soil_displacement_mean"] = soil_mean;
  results["soil_displacement_median"] = anchoring_soil_displacement(u, P, true, scratch);
  results["soil_displacement_at_T_max"] = u.soil_at_max;
  results["soil_displacement_ratio"] = soil_mean / s.max_displacement;
  results["anchoring_zone_grains"] = u.zone_count;
  results["sheet"] = {{"nodes", w.spars.nodes()}, {"elements", w.spars.elements()}};
  results["pull_steps"] = w.step - u.pull_start;
  results["dt"] = w.dt;
  results["grains"] = P.size();
  results["T_max"] = u.t_max;
  results["displacement_at_T_max"] = u.d_at_max;
  results["T_residual"] =
      u.late_rows > 0 ? u.late_sum / static_cast<double>(u.late_rows) : std::nan("");
  results["T_analytic_slip"] = u.est.tension;
  results["T_analytic_soil"] = u.est_soil.tension;
  const bool slip_governs = u.est.tension <= u.est_soil.tension;
  const double design = slip_governs ? u.est.tension : u.est_soil.tension;
  results["T_design"] = design;
  results["design_mechanism"] = slip_governs ? "slippage" : "soil_mass";
  results["T_max_over_analytic"] = u.est.tension > 0.0 ? u.t_max / u.est.tension : 0.0;
  results["T_max_over_design"] = design > 0.0 ? u.t_max / design : 0.0;
  const Mechanism m =
      classify_mechanism(u.d_at_max > 0.0 ? u.soil_median_at_max / u.d_at_max : 0.0,
                         u.nodes_at_max > 0.0 ? 1.0 - u.near_at_max / u.nodes_at_max : 1.0);
  results["mechanism"] = m.name;
  results["mechanism_measures"] = {{"soil_ratio", m.soil_ratio},
                                   {"sheet_slip_ratio", m.sheet_slip_ratio},
                                   {"soil_displacement_median_at_T_max", u.soil_median_at_max},
                                   {"near_sheet_displacement_at_T_max", u.near_at_max},
                                   {"sheet_displacement_at_T_max", u.nodes_at_max}};
  results["analytic"] = {{"unit_weight", u.unit_weight},
                         {"sigma_v0", u.est.sigma_v0},
                         {"surcharge_measured", u.sigma_q},
                         {"runout_load", u.runout_load},
                         {"K", u.est.K},
                         {"K_jaky", u.K_jaky},
                         {"K_wall", u.K_wall},
                         {"interface_friction_deg", s.macro_interface_deg()},
                         {"interface_adhesion", s.interface_adhesion},
                         {"soil_friction_deg", s.soil_friction_deg},
                         {"soil_cohesion", s.soil_cohesion},
                         {"soil_runout", u.est_soil.runout},
                         {"soil_trench", u.est_soil.trench},
                         {"runout_friction", u.est.runout},
                         {"trench_friction", u.est.trench},
                         {"capstan_factor", u.est.capstan}};
  results["sheet_parts"] = {{"at_T_max", sheet_parts_json(u.parts_at_max)},
                            {"at_start", sheet_parts_json(u.parts_first)},
                            {"slip_estimate", estimate_parts_json(u.est)}};
}

void write_pullout_states(const std::string& path_grains, const std::string& path_sheet,
                          const Particles<2>& P, const SparChains<2>& S,
                          const std::vector<int>& column_by_id) {
  std::filesystem::create_directories(std::filesystem::path(path_grains).parent_path());
  HistoryCsv g;
  g.open(path_grains, {"id", "x", "y", "radius", "column"});
  for (std::size_t i = 0; i < P.size(); ++i)
    g.row({static_cast<double>(P.id[i]), P.pos[i].x(), P.pos[i].y(), P.radius[i],
           static_cast<double>(column_by_id[P.id[i]])});
  HistoryCsv sh;
  // Per node: its position, the tension of the element that starts there, and at the
  // interior nodes the turn and the bending moment (N m/m) there.
  sh.open(path_sheet, {"node", "x", "y", "tension", "turn", "rest_turn", "moment"});
  for (std::size_t i = 0; i < S.nodes(); ++i) {
    const bool interior = i > 0 && i < S.elements() && S.next[i - 1] != kNoElement;
    sh.row({static_cast<double>(i), S.pos[i].x(), S.pos[i].y(),
            i < S.elements() ? S.tension[i] : 0.0, interior ? S.turn_angle(i - 1) : 0.0,
            interior ? S.rest_turn[i - 1] : 0.0, interior ? S.bending_moment(i - 1) : 0.0});
  }
}

}  // namespace geodem
