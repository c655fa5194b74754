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

#include "base/error.hpp"
#include "base/parallel.hpp"
#include "check_command.hpp"
#include "io/interrupt.hpp"
#include "io/plot_process.hpp"
#include "io/run_output.hpp"
#include "kinds/scenario_kind.hpp"
#include "study/study_comm.hpp"

namespace {

constexpr int kOk = 0, kFailure = 1, kBadInput = 2, kUnstable = 3;

int run_main(int argc, char** argv);

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
  int threads = geodem::default_threads(), ranks_per_run = 1, rebalance = 10;
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
  run->add_option("--ranks-per-run", ranks_per_run,
                  "studies under mpirun: each run spread over this many ranks (a group; the "
                  "ranks must be a multiple of it)")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  run->add_option("--rebalance", rebalance,
                  "a run over the ranks of mpirun: weigh each rank's work every N neighbour-list "
                  "builds and move the cuts between them when it is uneven (0: never)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  run->add_flag("--quiet", quiet, "no progress display");
  run->add_flag("--overwrite", overwrite,
                "replace the earlier run in --out (its files are deleted first); without it a "
                "folder that holds files is refused");
  run->add_option(
      "--resume", resume_dir,
      "continue the run whose output folder is DIR from its newest valid checkpoint "
      "(scene, triaxial and the element tests, pullout; outputs stay in DIR); a study: rerun its "
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
    geodem::LoadedScenario l = geodem::load_known_scenario(scenario, overrides);
    run_kind = l.kind;
    if (*check) return check_scenario(l, scenario, threads);
    const geodem::ScenarioKind& kind = geodem::find_kind(l, scenario);
    check_run_memory(l, scenario, threads);
    geodem::RunOptions opt;
    opt.out_dir = out_dir;
    opt.quiet = quiet;
    opt.threads = threads;
    opt.rebalance_every = rebalance;
    if (!resume_dir.empty()) {
      if (run->count("--out") && out_dir != resume_dir)
        throw geodem::InputError("", 0, "--out",
                                 "a resumed run writes to its own folder; give --resume DIR alone");
      if (overwrite)
        throw geodem::InputError("", 0, "--overwrite",
                                 "--resume continues the run in its folder; --overwrite would "
                                 "delete it: give one of them");
      if (!kind.resumable)
        throw geodem::InputError(scenario, l.kind_line, "kind",
                                 "kind \"" + l.kind +
                                     "\" writes no checkpoints: run it again with --out DIR "
                                     "--overwrite");
      opt.out_dir = out_dir = resume_dir;
      opt.resume = true;
    }
    const bool shared = kind.shares_ranks(l.root);
    if (ranks_per_run > 1) {
      if (!shared)
        throw geodem::InputError("", 0, "--ranks-per-run",
                                 "groups of ranks run the runs of a study (series, rate_study, "
                                 "calibrate); a scene or a lab test spreads over all the ranks "
                                 "of mpirun: leave --ranks-per-run out");
      if (geodem::comm::size() % ranks_per_run != 0)
        throw geodem::InputError("", 0, "--ranks-per-run",
                                 "the ranks of mpirun (" + std::to_string(geodem::comm::size()) +
                                     ") must be a multiple of the ranks per run (" +
                                     std::to_string(ranks_per_run) + ")");
      geodem::comm::split_into_groups(ranks_per_run);
    }
    // Under mpirun a study shares its runs across the ranks; a scene spreads its world over them
    // (with -n 1 too, so that 1, 2 and 4 ranks give the same bits).
    opt.decompose = geodem::comm::active() && !shared && kind.decomposes;
    opt.primary = !opt.decompose || geodem::comm::rank() == 0;
    if (geodem::comm::size() > 1 && !shared && !kind.decomposes)
      throw geodem::InputError(scenario, l.kind_line, "kind",
                               "under mpirun, studies (series, rate_study, calibrate) and "
                               "pull-outs over seeds share their runs across the ranks, and "
                               "scenes and the lab tests (but the simple shear) spread their "
                               "grains over them; run this kind without mpirun");
    // Single runs stop on SIGINT/SIGTERM after the step in progress, with a checkpoint;
    // runs shared as a study's keep the default (their finished runs are reused).
    if (!shared) geodem::install_interrupt_handlers();
    const geodem::KindRun done = kind.run(l, scenario, opt, overwrite);
    if (done.exit_code == kOk && !quiet && geodem::comm::rank() == 0)
      std::fprintf(stderr, "done: %s%soutputs in %s\n", done.done.c_str(),
                   done.done.empty() ? "" : "; ", out_dir.c_str());
    return done.exit_code;
  } catch (const geodem::InputError& e) {
    // Input errors, instabilities and signals reach every rank of mpirun alike: rank 0 says so.
    if (geodem::comm::rank() == 0) std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  } catch (const geodem::Interrupted& i) {
    if (geodem::comm::rank() == 0)
      std::fprintf(stderr, "interrupted by signal %d: outputs so far are in %s%s%s\n", i.signal,
                   out_dir.c_str(), i.checkpoint.empty() ? "" : "; continue with --resume ",
                   i.checkpoint.empty() ? "" : out_dir.c_str());
    return 128 + i.signal;
  } catch (const geodem::InstabilityError& e) {
    if (geodem::comm::rank() == 0)
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
    if (geodem::comm::size() == 1) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return kFailure;
    }
    // Met by this rank alone, maybe: the others are ended too rather than left waiting.
    std::fprintf(stderr, "error on rank %d: %s\n", geodem::comm::rank(), e.what());
    return geodem::comm::abort_all(kFailure);
  }
}
}  // namespace
