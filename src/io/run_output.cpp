#include "io/run_output.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>
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
  if (world.domain) {  // a run over the ranks of mpirun
    t["ranks"] = world.domain->ranks();
    t["rebalance_moves"] = world.domain->region_moves();
  }
  return t;
}

namespace {

// The grains this rank owns, as a world of their own (a frame's piece).
template <int D>
World<D> owned_grains(const World<D>& world) {
  World<D> own;
  own.time = world.time, own.step = world.step;
  own.particles = world.particles;
  own.clumps.id = world.clumps.id;  // (what the frame reads of a member's clump)
  std::vector<std::uint32_t> keep;
  for (std::size_t i = 0; i < world.particles.size(); ++i)
    if (!(world.particles.flags[i] & kGhost)) keep.push_back(static_cast<std::uint32_t>(i));
  own.particles.permute(keep);
  return own;
}

}  // namespace

template <int D>
void VtkSeries<D>::write(const World<D>& world) {
  using Vec = typename Dim<D>::Vec;
  char name[64];
  const bool root = !world.domain || world.domain->rank() == 0;
  // A decomposed domain's frame part: this rank's piece, and the names of every rank's.
  auto pieces = [&](const char* part, const char* ext, std::string& mine) {
    std::vector<std::string> all;
    for (int r = 0; r < world.domain->ranks(); ++r) {
      std::snprintf(name, sizeof name, "%s_%06d_%d.%s", part, count_, r, ext);
      all.push_back(name);
    }
    mine = all[static_cast<std::size_t>(world.domain->rank())];
    return all;
  };
  std::string piece;
  const World<D>* grains = &world;
  std::optional<World<D>> own;
  if (world.domain) {
    // A decomposed domain: each rank writes its own grains as a piece, rank 0 the index.
    own.emplace(owned_grains(world));
    grains = &*own;
    const auto all = pieces("particles", "vtu", piece);
    write_particles_vtu(dir_ + "/vtk/" + piece, *own, reference_);
    std::snprintf(name, sizeof name, "particles_%06d.pvtu", count_);
    if (root) write_particles_pvtu(dir_ + "/vtk/" + name, all, reference_ != nullptr);
  } else {
    std::snprintf(name, sizeof name, "particles_%06d.vtu", count_);
    write_particles_vtu(dir_ + "/vtk/" + name, world, reference_);
  }
  if (root) pvd_.add(world.time, name, 0);
  if (!world.walls.empty()) {
    // Draw planes a little larger than the grains' extent, centred on their centroid.
    const auto& P = grains->particles;
    const double inf = std::numeric_limits<double>::infinity();
    Vec lo = Vec::Constant(inf), hi = Vec::Constant(-inf), sum = Vec::Zero();
    double rmax = 0.0;
    for (std::size_t i = 0; i < P.size(); ++i)
      lo = lo.cwiseMin(P.pos[i]), hi = hi.cwiseMax(P.pos[i]), sum += P.pos[i],
      rmax = std::max(rmax, P.radius[i]);
    double count = static_cast<double>(P.size());
    if (world.domain) {
      std::vector<ExactSum> s(D + 1);
      for (int k = 0; k < D; ++k) s[k].add(sum[k]);
      s[D].add(count);
      world.domain->sum(s);
      for (int k = 0; k < D; ++k)
        sum[k] = s[k].value(), lo[k] = world.domain->min_over_ranks(lo[k]),
        hi[k] = -world.domain->min_over_ranks(-hi[k]);
      count = s[D].value();
      rmax = -world.domain->min_over_ranks(-rmax);
    }
    const double half = count > 0.0 ? 0.6 * (hi - lo).maxCoeff() + 2.0 * rmax : 0.0;
    const Vec centre = count > 0.0 ? Vec(sum / count) : Vec::Zero();
    std::snprintf(name, sizeof name, "walls_%06d.vtp", count_);
    if (root) {
      write_walls_vtp(dir_ + "/vtk/" + name, world, half, &centre);
      pvd_.add(world.time, name, 1);
    }
  }
  if (!world.spars.empty() && root) {  // (every rank holds the whole chains)
    std::snprintf(name, sizeof name, "spars_%06d.vtp", count_);
    write_spars_vtp(dir_ + "/vtk/" + name, world);
    pvd_.add(world.time, name, 2);
  }
  if (contacts_ && world.domain) {  // each rank its contacts, rank 0 the index
    const auto all = pieces("contacts", "vtp", piece);
    write_contacts_vtp(dir_ + "/vtk/" + piece, world);
    std::snprintf(name, sizeof name, "contacts_%06d.pvtp", count_);
    if (root) {
      write_contacts_pvtp(dir_ + "/vtk/" + name, all);
      pvd_.add(world.time, name, 3);
    }
  } else if (contacts_) {
    std::snprintf(name, sizeof name, "contacts_%06d.vtp", count_);
    write_contacts_vtp(dir_ + "/vtk/" + name, world);
    pvd_.add(world.time, name, 3);
  }
  if (world.cell.periodic && root) {  // (a decomposed cell's stress is the same on every rank)
    std::snprintf(name, sizeof name, "cell_%06d.vtp", count_);
    write_cell_vtp(dir_ + "/vtk/" + name, world);
    pvd_.add(world.time, name, 4);
  }
  if (root) pvd_.write();
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
void VtkSeries<D>::restore(StateReader& in, bool primary) {
  in(count_);
  std::uint64_t n = 0;
  in(n);
  if (n > in.left()) throw CheckpointError("VTK index beyond the data");
  auto& e = pvd_.entries();
  e.assign(n, {});
  for (auto& x : e) in(x.time), in(x.file), in(x.part);
  if (!primary) return;
  // Frames numbered count_ and above were written after the checkpoint (PART_FRAME.ext, or
  // PART_FRAME_RANK.vtu for a decomposed run's pieces).
  std::error_code ec;
  for (const auto& f : std::filesystem::directory_iterator(dir_ + "/vtk", ec)) {
    const std::string name = f.path().filename().string();
    const auto us = name.find('_'), end = name.find_first_of("_.", us + 1);
    if (us == std::string::npos || end == std::string::npos || end < us + 2) continue;
    const std::string digits = name.substr(us + 1, end - us - 1);
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
