#include "lab/pullout_results.hpp"

#include <filesystem>

#include "io/output_files.hpp"
#include "lab/anchorage_mechanism.hpp"

namespace geodem {

void pull_results(const Pull& u, const PulloutSettings& s, double macro_interface_deg,
                  nlohmann::json& results) {
  results["T_max"] = u.t_max;
  results["displacement_at_T_max"] = u.d_at_max;
  results["T_analytic_slip"] = u.est.tension;
  results["T_analytic_soil"] = u.est_soil.tension;
  const bool slip_governs = u.est.tension <= u.est_soil.tension;
  const double design = slip_governs ? u.est.tension : u.est_soil.tension;
  results["T_design"] = design;
  results["design_mechanism"] = slip_governs ? "slippage" : "soil_deformation";
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
                         {"interface_friction_deg", macro_interface_deg},
                         {"interface_adhesion", s.interface_adhesion},
                         {"soil_friction_deg", s.soil_friction_deg},
                         {"soil_cohesion", s.soil_cohesion},
                         {"soil_runout", u.est_soil.runout},
                         {"soil_trench", u.est_soil.trench},
                         {"runout_friction", u.est.runout},
                         {"trench_friction", u.est.trench},
                         {"capstan_factor", u.est.capstan}};
}

void write_pullout_states(const std::string& path_grains, const std::string& path_sheet,
                          const World<2>& w, const std::vector<int>& column_by_id) {
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

}  // namespace geodem
