// The pull of the pull-out test (lab/pullout_runner.hpp): the start of the pull, the free
// end pulled at a constant rate, the rows of the history and the tension profiles.
#include <algorithm>

#include "io/step_loop.hpp"
#include "lab/anchorage_mechanism.hpp"
#include "lab/pullout_runner.hpp"
#include "measure/measurements.hpp"

namespace geodem {

void PulloutRun::begin_pull() {
  auto& P = w.particles;
  auto& S = w.spars;
  prep["grains"] = grain_count();
  prep["bodies"] = body_count(w);
  prep["steps"] = w.step;
  prep["time"] = w.time;
  Pull& u = pull;
  // (one process numbers the grains from 0; a decomposed run keeps their ids)
  if (!domain)
    for (std::size_t i = 0; i < P.size(); ++i) P.id[i] = static_cast<std::uint32_t>(i);
  const double sigma_q = surcharge ? surcharge->pressure(w) : 0.0;
  const Particles<2>& grains = all_grains();
  start_pull(u, w, grains, s, y0, top, sigma_q);
  if (root)
    write_pullout_states(opt.out_dir + "/states/grains_initial.csv",
                         opt.out_dir + "/states/sheet_initial.csv", grains, w.spars, u.column);
  if (s.vtk) vtk.write(w);
  if (root) {
    history.open(opt.out_dir + "/history.csv", kHistoryColumns);
    profiles.open(opt.out_dir + "/tension_profiles.csv", kProfileColumns);
  }
  w.local_damping = s.pull_damping;
  S.vel[0] = Dim<2>::Vec(-s.rate, 0.0);
  phase = Phase::kPull;
}

void PulloutRun::pull_phase() {
  auto& S = w.spars;
  Pull& u = pull;
  const double d_record = s.max_displacement / s.history_points;
  step_loop(
      w, total_steps, [&] { return u.displacement < s.max_displacement; },
      [&] {
        const double next_d = u.clamp0.x() - (S.pos[0].x() - s.rate * w.dt);
        return next_d >= u.next_record || next_d >= s.max_displacement;
      },
      [&] { return record_pull(d_record); }, [&] { return after_step(); });
  phase = Phase::kDone;
}

namespace {
// A grain's value for a measure, and its id (the measures sum in id order).
struct ById {
  std::uint32_t id;
  double value;
};
}  // namespace

void PulloutRun::gather_row_measures(std::vector<double>& zone, std::vector<double>& near) {
  const auto& P = w.particles;
  const Pull& u = pull;
  std::vector<ById> mine_zone, mine_near;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.flags[i] & kGhost) continue;
    const std::uint32_t id = P.id[i];
    if (u.zone[id]) mine_zone.push_back({id, u.start[id].x() - P.pos[i].x()});
    if (u.near[id]) mine_near.push_back({id, (P.pos[i] - u.start[id]).norm()});
  }
  Bytes out;
  put_records(out, mine_zone);
  put_records(out, mine_near);
  const Bytes all = domain.current->comm().all_gather(out);
  std::vector<ById> all_zone, all_near;
  std::size_t at = 0;
  while (at < all.size()) append_records(all, at, all_zone), append_records(all, at, all_near);
  for (auto [from, to] : {std::pair{&all_zone, &zone}, std::pair{&all_near, &near}}) {
    std::sort(from->begin(), from->end(), [](const ById& a, const ById& b) { return a.id < b.id; });
    to->clear();
    for (const ById& g : *from) to->push_back(g.value);
  }
}

bool PulloutRun::record_pull(double d_record) {
  auto& S = w.spars;
  Pull& u = pull;
  u.displacement = u.clamp0.x() - S.pos[0].x();
  u.add_step(w);
  // The last row is always written, even when a change of dt made the prediction miss it.
  if (w.measure_this_step || u.displacement >= s.max_displacement) {
    SheetPartLoads parts;
    const double T = u.end_row(parts);
    double soil = 0.0, median = 0.0, near = 0.0;
    if (domain) {  // the same sums, in id order, as over every grain gathered
      gather_row_measures(moved, near_moved);
      soil = mean_of(moved), near = mean_of(near_moved);
      median = median_of(moved);
    } else {
      soil = anchoring_soil_displacement(u, w.particles, false, moved);
      median = anchoring_soil_displacement(u, w.particles, true, moved);
      near = mean_grain_displacement(w.particles, u.near, u.start);
    }
    const double nodes = mean_embedded_node_displacement(w, u.node_start);
    const std::vector<double> row = {static_cast<double>(w.step),
                                     w.time,
                                     u.displacement,
                                     T,
                                     S.tension[0],
                                     soil,
                                     median,
                                     kinetic_energy(w),
                                     unbalanced_force_ratio(w),
                                     static_cast<double>(w.stats.spar_contacts),
                                     near,
                                     nodes,
                                     parts.carried[kRunoutPart],
                                     parts.normal[kRunoutPart],
                                     parts.carried[kBendPart],
                                     parts.normal[kBendPart],
                                     parts.carried[kTrenchPart],
                                     parts.normal[kTrenchPart]};
    if (root) history.row(row);
    // Rows are equally spaced in displacement: their plain mean weighs the half evenly.
    if (u.displacement >= 0.5 * s.max_displacement) u.late_sum += T, ++u.late_rows;
    if (T > u.t_max) {
      u.t_max = T, u.d_at_max = u.displacement, u.soil_at_max = soil;
      u.soil_median_at_max = median, u.near_at_max = near, u.nodes_at_max = nodes;
      u.parts_at_max = parts;
    }
    while (u.next_record <= u.displacement) u.next_record += d_record;
    progress.update("pull", w.step, w.time, u.displacement / s.max_displacement,
                    "T " + format_sig(T) + " N/m");
  }
  while (!u.profile_at.empty() && u.displacement >= u.profile_at.back() - 1e-12) {
    double arc = 0.0;
    for (std::size_t e = 0; e < S.elements(); ++e) {
      const double len = S.length(e);
      if (root) profiles.row({u.profile_at.back(), arc + 0.5 * len, S.tension[e]});
      arc += len;
    }
    if (s.vtk) vtk.write(w);
    u.profile_at.pop_back();
  }
  return false;
}

}  // namespace geodem
