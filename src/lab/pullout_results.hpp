// The pull-out's measured state while the sheet is pulled, and what the test reports
// from it (docs/lab_tests.md, "Pull-out"; docs/anchorage_design.md): the design estimates,
// the mechanism, the analytic terms; and the grain and sheet state files.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lab/anchorage.hpp"
#include "lab/pullout_settings.hpp"
#include "lab/sheet_parts.hpp"
#include "world/world.hpp"

namespace geodem {

// The state of the pull, set up when the preparation ends.
struct Pull {
  // The anchoring soil: the fill above the run-out and in the trench, by grain id (none is
  // added or removed during the pull).
  std::vector<char> zone;
  std::vector<Dim<2>::Vec> start;
  std::vector<int> column;
  std::uint64_t zone_count = 0;
  // The grains next to the sheet (by id) and the nodes' start positions: the measures of
  // the mechanism (lab/anchorage_mechanism.hpp).
  std::vector<char> near;
  std::vector<Dim<2>::Vec> node_start;
  double unit_weight = 0.0, sigma_q = 0.0, runout_load = 0.0;
  double K_jaky = 0.0, K_wall = 0.0;  // earth pressure coefficients: Jaky's, measured
  SlipEstimate est;
  AnchorEstimate est_soil;
  std::vector<double> profile_at;  // displacements of the tension profiles to come
  Dim<2>::Vec clamp0 = Dim<2>::Vec::Zero();
  double next_record = 0.0, tension_sum = 0.0;
  std::uint64_t tension_steps = 0;
  double t_max = 0.0, d_at_max = 0.0, soil_at_max = 0.0, displacement = 0.0;
  double soil_median_at_max = 0.0, near_at_max = 0.0, nodes_at_max = 0.0;
  // The rows of the pull's second half: their tensions' sum and count (T_residual, the
  // sliding resistance; a peak can be a short jam of grains against the sheet).
  double late_sum = 0.0;
  std::uint64_t late_rows = 0;
  std::uint64_t pull_start = 0;
  // The sheet's parts (lab/sheet_parts.hpp): the bend's corner (none for a run-out) and its
  // band; the sums of the current row, the first row's means and those of T_max's row.
  std::uint8_t has_corner = 0;
  Dim<2>::Vec corner = Dim<2>::Vec::Zero();
  double corner_band = 0.0;
  SheetPartLoads parts_sum, parts_first, parts_at_max;
  std::uint8_t parts_first_set = 0;

  template <class Archive>
  void visit(Archive& a) {
    a(zone), a(start), a(column), a(zone_count), a(near), a(node_start), a(unit_weight);
    a(sigma_q), a(runout_load), a(K_jaky), a(K_wall), a(est), a(est_soil), a(profile_at), a(clamp0),
        a(next_record);
    a(tension_sum), a(tension_steps), a(t_max), a(d_at_max), a(soil_at_max), a(displacement);
    a(soil_median_at_max), a(near_at_max), a(nodes_at_max), a(pull_start);
    a(has_corner), a(corner), a(corner_band), a(parts_sum), a(parts_first), a(parts_at_max);
    a(parts_first_set), a(late_sum), a(late_rows);
  }

  // Adds a step of the pull to the row's sums: the clamp's tension and the sheet's parts.
  void add_step(const World<2>& w) {
    tension_sum += w.spars.tension[0];
    parts_sum +=
        sheet_part_loads(w.spars, has_corner ? std::optional(corner) : std::nullopt, corner_band);
    ++tension_steps;
  }
  // Ends a row: its mean tension (returned) and parts over the steps since the previous row,
  // since the per-step values carry the sheet's own vibrations; the sums start again.
  double end_row(SheetPartLoads& parts) {
    const double n = static_cast<double>(tension_steps), T = tension_sum / n;
    parts = parts_sum.scaled(1.0 / n);
    if (!parts_first_set) parts_first = parts, parts_first_set = 1;
    tension_sum = 0.0, parts_sum = SheetPartLoads{}, tension_steps = 0;
    return T;
  }
};

// The columns of the pull-out's preparation.csv, history.csv and tension_profiles.csv.
inline const std::vector<std::string> kPrepColumns = {
    "stage", "step", "time", "grains", "surface", "unbalanced", "kinetic_energy"};
inline const std::vector<std::string> kHistoryColumns = {"step",
                                                         "time",
                                                         "displacement",
                                                         "tension",
                                                         "tension_step",
                                                         "soil_displacement",
                                                         "soil_displacement_median",
                                                         "kinetic_energy",
                                                         "unbalanced",
                                                         "sheet_contacts",
                                                         "near_sheet_displacement",
                                                         "sheet_displacement",
                                                         "runout_carried",
                                                         "runout_normal",
                                                         "bend_carried",
                                                         "bend_normal",
                                                         "trench_carried",
                                                         "trench_normal"};
inline const std::vector<std::string> kProfileColumns = {"displacement", "s", "tension"};

// The grains `P` of these functions are the whole sample's: the world's own in one process,
// every rank's gathered in id order in a decomposed run (scene/scene_domain.hpp).

// The pull's state when the preparation ends: the anchoring zone, the grains' start
// positions and bands (arrays by grain id), the unit weight of the cover and the load on the
// run-out, the earth pressure coefficients, both design estimates (with the macroscopic
// interface friction) and the grains next to the sheet. `y0` is the run-out level, `top` the
// cover's surface, `sigma_q` the surcharge. Resets the pull's counters (records, profiles, the
// largest tension so far).
void start_pull(Pull& u, const World<2>& w, const Particles<2>& P, const PulloutSettings& s,
                double y0, double top, double sigma_q);

// Displacement of the anchoring soil towards the pull: the mean, or the median (which
// grains that roll off a free face far from the anchor do not pull up).
double anchoring_soil_displacement(const Pull& u, const Particles<2>& P, bool median,
                                   std::vector<double>& scratch);
// The mean of v's values summed in their order (0 when empty), and their median (the upper
// one of an even count; v is reordered).
double mean_of(const std::vector<double>& v);
double median_of(std::vector<double>& v);

// The estimates, the mechanism, the analytic terms and the soil's displacement of a
// finished pull, with the chains of the final world `w` and its grains `P`, into `results`.
void pull_results(const Pull& u, const World<2>& w, const Particles<2>& P, const PulloutSettings& s,
                  nlohmann::json& results);

// Grains (id, x, y, radius, column: the band each grain was in when the pull started) and
// the sheet's nodes (with the tension of the element that starts there).
void write_pullout_states(const std::string& path_grains, const std::string& path_sheet,
                          const Particles<2>& P, const SparChains<2>& S,
                          const std::vector<int>& column_by_id);

}  // namespace geodem
