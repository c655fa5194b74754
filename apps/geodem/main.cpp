// geodem command line: run, check, plot (docs/cli.md).
// Exit codes: 0 success, 2 bad input, 3 unstable simulation, 1 anything else.
#include <malloc.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "check_command.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "io/interrupt.hpp"
#include "io/run_output.hpp"
#include "io/scenario_file.hpp"
#include "lab/run_interface_shear.hpp"
#include "lab/run_pullout.hpp"
#include "lab/run_triaxial.hpp"
#include "scene/build_scene.hpp"
#include "scene/run_scene.hpp"
#include "study/run_studies.hpp"
#include "study/study_comm.hpp"

namespace {

constexpr int kOk = 0, kFailure = 1, kBadInput = 2, kUnstable = 3;

using Loaded = geodem::LoadedScenario;

Loaded load(const std::string& file, const std::vector<std::string>& overrides) {
  return geodem::load_scenario(file, overrides);
}

int run_main(int argc, char** argv);

// A new run's output folder (io/run_output.hpp, claim_output_dir): rank 0 decides (and
// empties the folder on --overwrite) before any rank writes into it.
void claim_output(const geodem::RunOptions& opt, bool overwrite) {
  if (opt.resume) return;
  std::string refusal;
  if (geodem::comm::rank() == 0) refusal = geodem::claim_output_dir(opt.out_dir, overwrite);
  if (geodem::comm::size() > 1) refusal = geodem::comm::all_gather(refusal)[0];
  if (!refusal.empty()) throw geodem::InputError("", 0, "--out", refusal);
}

// Studies: their runs go to `--threads` workers on each MPI rank; rank 0 reports.
int run_study(const Loaded& l, const std::string& file, const geodem::RunOptions& opt,
              bool overwrite) {
  nlohmann::json summary;
  bool plots = true;
  if (l.kind == "series") {
    const auto s = geodem::read_series(l.root, file);
    claim_output(opt, overwrite);
    summary = geodem::run_series(s, opt);
    plots = s.study.plots;
  } else if (l.kind == "rate_study") {
    const auto s = geodem::read_rate_study(l.root, file);
    claim_output(opt, overwrite);
    summary = geodem::run_rate_study(s, opt);
    plots = s.study.plots;
  } else if (geodem::is_interface_calibration(l.root)) {
    const auto s = geodem::read_interface_calibrate(l.root, file);
    claim_output(opt, overwrite);
    summary = geodem::run_interface_calibrate(s, opt);
    plots = s.plots;
  } else {
    const auto s = geodem::read_calibrate(l.root, file);
    claim_output(opt, overwrite);
    summary = geodem::run_calibrate(s, opt);
    plots = s.study.plots;
  }
  if (geodem::comm::rank() != 0) return kOk;
  if (plots) geodem::make_plots(opt.out_dir, opt.quiet);
  const auto& failed = summary["results"]["failed_runs"];
  if (!failed.empty()) {
    std::fprintf(stderr, "warning: %zu run(s) did not complete (results.failed_runs):\n",
                 failed.size());
    bool unstable = false;
    for (const auto& f : failed) {
      std::fprintf(stderr, "  %s: %s\n", f["id"].get<std::string>().c_str(),
                   f["error"].get<std::string>().c_str());
      unstable = unstable || f["status"] == "unstable";
    }
    return unstable ? kUnstable : kFailure;
  }
  if (!opt.quiet) std::fprintf(stderr, "done: outputs in %s\n", opt.out_dir.c_str());
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    geodem::comm::init(&argc, &argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  const int rc = run_main(argc, argv);
  geodem::comm::finalize();
  return rc;
}

namespace {
int run_main(int argc, char** argv) {
  // Grain and contact arrays are large and are reallocated when the neighbour list grows or
  // the grains are renumbered. A fixed mmap threshold gives each such block pages of its
  // own that go back to the system when it is freed; glibc's adaptive threshold would
  // otherwise move them into the heap, whose holes stay resident (B2 bed of 20,000 spheres:
  // 22.4 MB peak before, 14.4 MB with this and orientations left unstored).
  mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  CLI::App app{"geodem: discrete element method for geotechnical engineering"};
  app.set_version_flag("--version", std::string("geodem ") + geodem::version() +
                                        (geodem::comm::built_with_mpi() ? " (MPI)" : ""));
  app.require_subcommand(1);

  std::string scenario, out_dir = "out", plot_dir, resume_dir, run_kind;
  std::vector<std::string> overrides;
  int threads = geodem::default_threads();
  bool quiet = false, overwrite = false;

  auto* run = app.add_subcommand("run", "run a scenario");
  run->add_option("scenario", scenario, "scenario file (TOML)")->required();
  run->add_option("--out", out_dir, "output folder")->capture_default_str();
  run->add_option("--set", overrides, "override a scenario key: --set sample.count=2000");
  run->add_option("--threads", threads,
                  "threads of the step; studies: runs side by side on each MPI rank "
                  "(default: GEODEM_THREADS, else OMP_NUM_THREADS, else 1)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  run->add_flag("--quiet", quiet, "no progress display");
  run->add_flag("--overwrite", overwrite,
                "replace the earlier run in --out (its files are deleted first); without it a "
                "folder that holds files is refused");
  run->add_option("--resume", resume_dir,
                  "continue the run whose output folder is DIR from its newest valid checkpoint "
                  "(scene, triaxial, pullout; outputs stay in DIR); a study: rerun its "
                  "unfinished runs, keeping the finished ones");

  auto* check = app.add_subcommand("check", "validate a scenario without running it");
  check->add_option("scenario", scenario, "scenario file (TOML)")->required();
  check->add_option("--set", overrides, "override a scenario key");
  check->add_option("--threads", threads, "a study's runs side by side, for its memory estimate")
      ->check(CLI::Range(1, 1024));

  auto* plot = app.add_subcommand("plot", "(re)make the PNG plots of a finished run");
  plot->add_option("dir", plot_dir, "output folder of a run")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? kOk : kBadInput;
  }

  try {
    if (*plot) {
      if (!std::filesystem::exists(plot_dir + "/summary.json")) {
        std::fprintf(stderr, "error: %s/summary.json not found: not a finished run's folder\n",
                     plot_dir.c_str());
        return kBadInput;
      }
      return geodem::make_plots(plot_dir, false) ? kOk : kFailure;
    }
    Loaded l = load(scenario, overrides);
    run_kind = l.kind;
    if (*check) return check_scenario(l, scenario, threads);
    check_run_memory(l, scenario, threads);
    geodem::RunOptions opt;
    opt.out_dir = out_dir;
    opt.quiet = quiet;
    opt.threads = threads;
    if (!resume_dir.empty()) {
      if (run->count("--out") && out_dir != resume_dir)
        throw geodem::InputError("", 0, "--out",
                                 "a resumed run writes to its own folder; give --resume DIR alone");
      if (overwrite)
        throw geodem::InputError("", 0, "--overwrite",
                                 "--resume continues the run in its folder; --overwrite would "
                                 "delete it: give one of them");
      if (l.kind == "interface_shear")
        throw geodem::InputError(scenario, 0, "kind",
                                 "an interface shear test writes no checkpoints: run it again "
                                 "with --out DIR --overwrite");
      opt.out_dir = out_dir = resume_dir;
      opt.resume = true;
    }
    if (l.kind == "series" || l.kind == "rate_study" || l.kind == "calibrate")
      return run_study(l, scenario, opt, overwrite);
    // A pull-out over seeds or grain sizes runs its runs as a study does.
    const bool pullout_series =
        l.kind == "pullout" && (l.root["seeds"].value_or(1LL) > 1 || l.root.contains("refinement"));
    if (geodem::comm::size() > 1 && !pullout_series)
      throw geodem::InputError(scenario, 0, "kind",
                               "only studies (series, rate_study, calibrate) and pull-outs over "
                               "seeds share their runs across MPI ranks; run this scenario "
                               "without mpirun");
    // Single runs stop on SIGINT/SIGTERM after the step in progress, with a checkpoint;
    // studies keep the default (their finished runs are reused on rerunning).
    if (!pullout_series) geodem::install_interrupt_handlers();
    if (l.kind == "triaxial") {
      const geodem::TriaxialSettings t = geodem::read_triaxial(l.root, scenario);
      claim_output(opt, overwrite);
      geodem::run_triaxial(t, opt);
      if (t.plots) geodem::make_plots(out_dir, quiet);
      if (!quiet) std::fprintf(stderr, "done: outputs in %s\n", out_dir.c_str());
      return kOk;
    }
    if (l.kind == "pullout") {
      const geodem::PulloutSettings p = geodem::read_pullout(l.root, scenario);
      if (p.seeds > 1 || !p.radius_factors.empty()) {
        claim_output(opt, overwrite);  // a resumed series keeps its finished runs
        const auto summary = geodem::run_pullout_series(l.root, p, opt);
        if (geodem::comm::rank() != 0) return kOk;
        if (p.plots) geodem::make_plots(out_dir, quiet);
        const auto& t = summary["results"]["T_max"];
        if (!quiet && t.is_object())
          std::fprintf(stderr, "done: T_max %.4g N/m (mean of %d seeds, cv %.2g); outputs in %s\n",
                       t["mean"].get<double>(), p.seeds, t["cv"].get<double>(), out_dir.c_str());
        return summary["results"]["failed_runs"].empty() ? kOk : kFailure;
      }
      claim_output(opt, overwrite);
      const auto summary = geodem::run_pullout(p, opt);
      if (p.plots) geodem::make_plots(out_dir, quiet);
      if (!quiet)
        std::fprintf(stderr,
                     "done: T_max %.4g N/m, mechanism %s (design: slippage %.4g N/m, soil mass "
                     "%.4g N/m); outputs in %s\n",
                     summary["results"]["T_max"].get<double>(),
                     summary["results"]["mechanism"].get<std::string>().c_str(),
                     summary["results"]["T_analytic_slip"].get<double>(),
                     summary["results"]["T_analytic_soil"].get<double>(), out_dir.c_str());
      return kOk;
    }
    if (l.kind == "interface_shear") {
      const geodem::InterfaceShearSettings p = geodem::read_interface_shear(l.root, scenario);
      claim_output(opt, overwrite);
      const auto summary = geodem::run_interface_shear(p, opt);
      if (p.plots) geodem::make_plots(out_dir, quiet);
      if (!quiet)
        std::fprintf(stderr,
                     "done: interface friction %.4g deg (peak), %.4g deg (residual); outputs in "
                     "%s\n",
                     summary["results"]["interface_friction_peak_deg"].get<double>(),
                     summary["results"]["interface_friction_residual_deg"].get<double>(),
                     out_dir.c_str());
      return kOk;
    }
    const geodem::SceneSettings s = geodem::read_scene(l.root, scenario);
    claim_output(opt, overwrite);
    const auto summary = geodem::run_scene(s, opt);
    if (s.output.plots) geodem::make_plots(out_dir, quiet);
    if (!quiet)
      std::fprintf(stderr, "done: %s steps, %.3g s simulated; outputs in %s\n",
                   summary["results"]["steps"].dump().c_str(),
                   summary["results"]["time"].get<double>(), out_dir.c_str());
    return kOk;
  } catch (const geodem::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  } catch (const geodem::Interrupted& i) {
    std::fprintf(stderr, "interrupted by signal %d: outputs so far are in %s%s%s\n", i.signal,
                 out_dir.c_str(), i.checkpoint.empty() ? "" : "; continue with --resume ",
                 i.checkpoint.empty() ? "" : out_dir.c_str());
    return 128 + i.signal;
  } catch (const geodem::InstabilityError& e) {
    std::fprintf(stderr, "unstable: %s\nthe outputs written so far are in %s\n", e.what(),
                 out_dir.c_str());
    return kUnstable;
  } catch (const std::bad_alloc&) {
    // The estimate let it start (io/memory_budget.hpp), but the machine ran out: say so,
    // and leave a summary that says so beside the outputs written so far.
    std::fprintf(stderr,
                 "error: out of memory: the run needed more than the machine could give "
                 "(lower the grain count, or --threads for a study); the outputs written so far "
                 "are in %s\n",
                 out_dir.c_str());
    if (*run && std::filesystem::exists(out_dir)) {
      try {
        geodem::write_stopped_summary(out_dir, run_kind, nlohmann::json::object(), "failed",
                                      "out of memory", "", threads);
      } catch (...) {
      }
    }
    return kFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kFailure;
  }
}
}  // namespace
