#include "io/run_output.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "io/output_files.hpp"

#ifndef GEODEM_VERSION
#define GEODEM_VERSION "0.0.0"
#endif

namespace geodem {

const char* version() {
  return GEODEM_VERSION;
}

void prepare_output_dir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir + "/vtk", ec);
  if (ec) throw std::runtime_error("cannot create output folder " + dir + ": " + ec.message());
}

std::string claim_output_dir(const std::string& dir, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(dir, ec) || fs::is_empty(dir, ec)) return "";
  if (!fs::is_directory(dir, ec)) return dir + " exists and is not a folder; choose another --out";
  // What a geodem run leaves: only such a folder is emptied by --overwrite.
  bool a_run = false;
  for (const char* mark :
       {"summary.json", "checkpoint", "history.csv", "preparation.csv", "runs", "vtk"})
    a_run = a_run || fs::exists(fs::path(dir) / mark, ec);
  if (!a_run)
    return dir + " is not empty and holds no geodem run (no summary.json, history.csv or " +
           "checkpoint/): choose another --out; --overwrite does not empty it";
  if (!overwrite)
    return dir + " holds an earlier run: give --overwrite to replace it (its files are " +
           "deleted first), --resume " + dir + " to continue it, or another --out";
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    fs::remove_all(entry.path(), ec);
    if (ec) return "cannot empty " + dir + " (" + entry.path().string() + ": " + ec.message() + ")";
  }
  return "";
}

void write_summary(const std::string& dir, const nlohmann::json& summary) {
  write_file_atomic(dir + "/summary.json", summary.dump(2) + "\n");
}

nlohmann::json write_run_summary(const std::string& dir, const std::string& kind,
                                 const std::string& status, const nlohmann::json& scenario,
                                 const nlohmann::json& results, const nlohmann::json& timing) {
  nlohmann::json summary;
  summary["kind"] = kind;
  summary["geodem_version"] = version();
  summary["status"] = status;
  summary["scenario"] = scenario;
  summary["results"] = results;
  summary["timing"] = timing;
  write_summary(dir, summary);
  return summary;
}

template <int D>
nlohmann::json timing_json(const World<D>& world, double wall_s, std::uint64_t steps, int threads) {
  nlohmann::json t;
  t["wall_s"] = wall_s;
  t["steps"] = steps;
  t["particles"] = world.particles.size();
  t["particle_steps_per_s"] =
      wall_s > 0.0
          ? static_cast<double>(steps) * static_cast<double>(world.particles.size()) / wall_s
          : 0.0;
  t["threads"] = threads;
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < static_cast<int>(Stage::kCount); ++s)
    stages[stage_name(static_cast<Stage>(s))] = world.stage_seconds[s];
  t["stages_s"] = stages;
  t["neighbour_list_builds"] = world.nlist.builds;
  return t;
}

template <int D>
void VtkSeries<D>::write(const World<D>& world) {
  char name[64];
  std::snprintf(name, sizeof name, "particles_%06d.vtu", count_);
  write_particles_vtu(dir_ + "/vtk/" + name, world, reference_);
  pvd_.add(world.time, name, 0);
  if (!world.walls.empty()) {
    std::snprintf(name, sizeof name, "walls_%06d.vtp", count_);
    // Draw planes a little larger than the grains' extent.
    double half = 0.0;
    const auto& P = world.particles;
    if (!P.pos.empty()) {
      auto lo = P.pos[0], hi = P.pos[0];
      for (const auto& x : P.pos) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
      half = 0.6 * (hi - lo).maxCoeff() + 2.0 * P.radius[0];
    }
    write_walls_vtp(dir_ + "/vtk/" + name, world, half);
    pvd_.add(world.time, name, 1);
  }
  if (!world.spars.empty()) {
    std::snprintf(name, sizeof name, "spars_%06d.vtp", count_);
    write_spars_vtp(dir_ + "/vtk/" + name, world);
    pvd_.add(world.time, name, 2);
  }
  if (contacts_) {
    std::snprintf(name, sizeof name, "contacts_%06d.vtp", count_);
    write_contacts_vtp(dir_ + "/vtk/" + name, world);
    pvd_.add(world.time, name, 3);
  }
  if (world.cell.periodic) {
    std::snprintf(name, sizeof name, "cell_%06d.vtp", count_);
    write_cell_vtp(dir_ + "/vtk/" + name, world);
    pvd_.add(world.time, name, 4);
  }
  pvd_.write();
  ++count_;
}

void write_stopped_summary(const std::string& dir, const std::string& kind,
                           const nlohmann::json& scenario, const std::string& status,
                           const std::string& reason, const std::string& checkpoint, int threads) {
  nlohmann::json results = {{"status", status}, {"stop_reason", reason}};
  if (!checkpoint.empty()) results["checkpoint"] = checkpoint;
  write_run_summary(dir, kind, status, scenario, results, {{"threads", threads}});
}

template <int D>
void VtkSeries<D>::save(StateWriter& out) const {
  out(count_);
  const auto& e = pvd_.entries();
  out(static_cast<std::uint64_t>(e.size()));
  for (const auto& x : e) out(x.time), out(x.file), out(x.part);
}

template <int D>
void VtkSeries<D>::restore(StateReader& in) {
  in(count_);
  std::uint64_t n = 0;
  in(n);
  if (n > in.left()) throw CheckpointError("VTK index beyond the data");
  auto& e = pvd_.entries();
  e.assign(n, {});
  for (auto& x : e) in(x.time), in(x.file), in(x.part);
  // Frames numbered count_ and above were written after the checkpoint.
  std::error_code ec;
  for (const auto& f : std::filesystem::directory_iterator(dir_ + "/vtk", ec)) {
    const std::string name = f.path().filename().string();
    const auto us = name.rfind('_'), dot = name.rfind('.');
    if (us == std::string::npos || dot == std::string::npos || dot < us + 2) continue;
    const std::string digits = name.substr(us + 1, dot - us - 1);
    if (digits.size() > 12 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    if (std::stoll(digits) >= count_) std::filesystem::remove(f.path(), ec);
  }
  // The index as the run had it: none before its first frame (a run without frames, such
  // as a study's, leaves its vtk/ folder empty).
  if (count_ > 0) pvd_.write();
}

template class VtkSeries<2>;
template class VtkSeries<3>;
template nlohmann::json timing_json<2>(const World<2>&, double, std::uint64_t, int);
template nlohmann::json timing_json<3>(const World<3>&, double, std::uint64_t, int);

}  // namespace geodem
