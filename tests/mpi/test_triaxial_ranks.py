#!/usr/bin/env python3
"""`mpirun -n K geodem run triaxial.toml` spreads one triaxial test over K ranks with the same
bits for any K: a 2D test of bonded pair clumps with rolling friction (radius growth with the
ghost width following it, friction reduction, bonds made after the compaction, two
compressions each started from the prepared sample, VTK frames in pieces) on 1 and 2 (two
threads each) ranks, and a 3D test of spheres on 1, 2 and 4 ranks (oversubscribed), write the
same history.csv, preparation.csv and results. Killed (SIGKILL after periodic checkpoints, or SIGTERM) and resumed
on another number of ranks, or by one process without mpirun, they write the files of the
uninterrupted run. The element tests with walls (oedometer, isotropic, cyclic, direct shear)
give the same bits on 1 and 2 ranks. A series study whose runs go to groups of 2 ranks
(`--ranks-per-run 2`) gives the same results on 1 and 2 groups. Slabs thinner than the ghost
width the compaction will grow to are refused with exit code 2 before the run starts (the tests
in a periodic cell: test_cell_ranks.py).

    test_triaxial_ranks.py PATH/TO/geodem
Exit 77 (skipped) without mpirun or without MPI in geodem.
"""
import json
import os
import signal
import subprocess
import sys
import tempfile

from test_scene_ranks import check, failures, history, mpi_launch, pieces, stop_at_checkpoint

HERE = os.path.dirname(os.path.abspath(__file__))


def outputs(out):
    """What two runs of one test must share."""
    return {"history": history(os.path.join(out, "history.csv")),
            "preparation": open(os.path.join(out, "preparation.csv")).read(),
            "results": json.load(open(os.path.join(out, "summary.json")))["results"]}


def main() -> int:
    geodem = sys.argv[1]
    launch = mpi_launch(geodem)
    if launch is None:
        return 77
    mpirun, env = launch

    def run(ranks, scenario, out, *extra, threads=1):
        launcher = [mpirun, "-n", str(ranks)] if ranks else []
        args = launcher + [geodem, "run", scenario, "--out", out, "--quiet", "--threads",
                           str(threads)] + list(extra)
        return subprocess.run(args, env=env, text=True, capture_output=True, timeout=600)

    with tempfile.TemporaryDirectory() as tmp:
        refs = {}
        for name in ("triaxial2d.toml", "triaxial3d.toml"):
            scenario = os.path.join(HERE, name)
            # (the 2D test on 4 ranks: its resumed run below)
            for ranks in (1, 2) if name == "triaxial2d.toml" else (1, 2, 4):
                out = os.path.join(tmp, f"{name}.{ranks}")
                r = run(ranks, scenario, out, threads=2 if ranks == 2 else 1)
                if r.returncode != 0:
                    check(False, f"{name} on {ranks} ranks ran: {r.stdout}{r.stderr}")
                    continue
                got = outputs(out)
                res = got["results"]
                timing = json.load(open(os.path.join(out, "summary.json")))["timing"]
                grains = 600 if name == "triaxial2d.toml" else 400
                # (the 3D test stops at 1 % axial strain, before its peak)
                least = 15.0 if name == "triaxial2d.toml" else 5.0
                check(timing["ranks"] == ranks and timing["particles"] == grains and
                      len(res["tests"]) == (2 if name == "triaxial2d.toml" else 1) and
                      all(t["phi_peak_deg"] > least for t in res["tests"]),
                      f"{name} on {ranks} ranks: {len(res['tests'])} tests, peak friction "
                      f"angles {[round(t['phi_peak_deg'], 2) for t in res['tests']]} deg, "
                      f"{timing['particles']} grains")
                if name == "triaxial2d.toml":
                    count, ids = pieces(out)
                    check(res["preparation"]["bonds"] > 0 and
                          res["preparation"]["compaction_friction_deg"] < 25.0 and
                          count == ranks and sorted(ids) == list(range(grains)),
                          f"{name} on {ranks} ranks: {res['preparation']['bonds']} bonds made, "
                          f"friction reduced to {res['preparation']['compaction_friction_deg']:.1f}"
                          f" deg, the last frame in {count} pieces holding every member once")
                if ranks == 1:
                    refs[name] = got
                    continue
                for part in got:
                    check(got[part] == refs[name][part],
                          f"{name}: {part} on {ranks} ranks the same as on 1 rank")

        # The element tests with walls, from a smaller 2D sample (150 clumps, denser at the
        # start, no friction reduction): 1 and 2 ranks the same bits.
        with open(os.path.join(HERE, "triaxial2d.toml")) as f:
            sample = "".join(line for line in f.read().split("[shear]")[0].splitlines(True)
                             if not line.startswith("target_porosity"))
        sample = sample.replace("box = [0.8, 0.8]", "box = [0.4, 0.8]") \
            .replace("count = 300", "count = 150") \
            .replace("initial_porosity = 0.9", "initial_porosity = 0.75")
        elements = {
            "oedometer": "[loading]\nstresses = [2e5, 1e5]\n",
            "isotropic": "[loading]\nstresses = [2e5, 1e5]\n",
            "cyclic_triaxial": "[loading]\namplitudes = [1e-4, 1e-3]\ncycles = 1\n"
                               "steps_per_cycle = 400\n",
            "direct_shear": "[loading]\nnormal_stress = [1e5]\nmax_displacement = 0.004\n"}
        for kind, loading in elements.items():
            scenario = os.path.join(tmp, kind + ".toml")
            text = sample.replace('kind = "triaxial"', f'kind = "{kind}"')
            if kind == "direct_shear":  # (a box longer than high)
                text = text.replace("box = [0.4, 0.8]", "box = [0.8, 0.4]")
            with open(scenario, "w") as f:
                f.write(text + loading + "[output]\nplots = false\n")
            got = []
            for ranks in (1, 2):
                out = os.path.join(tmp, f"{kind}.{ranks}")
                r = run(ranks, scenario, out)
                if r.returncode != 0:
                    check(False, f"{kind} on {ranks} ranks ran: {r.stdout}{r.stderr}")
                    break
                got.append(outputs(out))
            if len(got) == 2:
                rows = len(got[0]["history"]) - 1
                check(rows >= 10 and got[0] == got[1],
                      f"{kind}: history ({rows} rows), preparation and results on 2 ranks the "
                      f"same as on 1 rank")

        # A study's runs on groups of 2 ranks (--ranks-per-run 2): one group running both runs
        # (mpirun -n 2) and two groups running one each (-n 4) give the same study, and a run
        # has the bits of its scenario run alone on 2 ranks.
        study = os.path.join(tmp, "series.toml")
        with open(study, "w") as f:
            f.write('kind = "series"\n' + sample.replace('kind = "triaxial"\n', "")
                    .replace('grain = "pair_0.9"\n', "") + "[shear]\nstrain_rate = 0.1\n"
                    "max_axial_strain = 0.01\nconfining_stress = [1e5]\n"
                    "[series]\ncounts = [100, 150]\nseeds = 1\n[output]\nplots = false\n")
        studies = []
        for ranks in (2, 4):
            out = os.path.join(tmp, f"series.{ranks}")
            r = run(ranks, study, out, "--ranks-per-run", "2")
            if r.returncode != 0:
                check(False, f"the series on {ranks} ranks in groups of 2 ran: {r.stderr}")
                continue
            studies.append(json.load(open(os.path.join(out, "summary.json"))))
        if len(studies) == 2:
            alone = os.path.join(tmp, "series.alone")
            runs = os.path.join(tmp, "series.4", "runs")
            run_dir = os.path.join(runs, sorted(os.listdir(runs))[-1])  # (150 grains)
            r = run(2, os.path.join(run_dir, "scenario.toml"), alone)
            check(studies[0]["results"] == studies[1]["results"] and
                  studies[1]["timing"]["ranks_per_run"] == 2 and r.returncode == 0 and
                  outputs(alone) == outputs(run_dir),
                  "a series in groups of 2 ranks: the same on 1 and 2 groups, and a run the bits "
                  "of its scenario alone on 2 ranks")
        r = run(2, os.path.join(HERE, "triaxial3d.toml"), os.path.join(tmp, "no_study"),
                "--ranks-per-run", "2")
        check(r.returncode == 2 and "--ranks-per-run" in r.stderr,
              f"--ranks-per-run on a single test refused: exit {r.returncode}")

        # Killed, then resumed on another number of ranks: the files of the uninterrupted run.
        # SIGKILL leaves the last periodic checkpoint (here after the prepared sample is kept:
        # both samples' domains are in it); SIGTERM stops every rank at a step they agree on.
        for name, first, then, sig, at in (("triaxial2d.toml", 2, 4, signal.SIGKILL, 65000),
                                           ("triaxial3d.toml", 4, 0, signal.SIGTERM, 15000)):
            out = os.path.join(tmp, f"{name}.killed")
            scenario = os.path.join(HERE, name)
            args = [mpirun, "-n", str(first), geodem, "run", scenario, "--out", out, "--quiet",
                    "--set", "checkpoint.every_steps=5000"]
            ck = stop_at_checkpoint(args, env, out, at, sig)
            if ck is None:
                check(False, f"{name} on {first} ranks ended before it was killed")
                continue
            launcher = [mpirun, "-n", str(then)] if then else []
            r = subprocess.run(launcher + [geodem, "run", scenario, "--resume", out, "--quiet",
                                           "--set", "checkpoint.every_steps=5000"],
                               env=env, text=True, capture_output=True, timeout=600)
            same = r.returncode == 0 and outputs(out) == refs.get(name)
            check(same, f"{name}: {sig.name} on {first} ranks (checkpoints {ck[-1:]}), resumed "
                        f"on {then or 'one process without mpirun'}: history, preparation and "
                        f"results of the uninterrupted run {'' if r.returncode == 0 else r.stderr}")

        # Slabs too thin: exit 2 with a message naming the file and the key.
        narrow = os.path.join(tmp, "narrow.toml")
        with open(os.path.join(HERE, "triaxial2d.toml")) as f:
            text = f.read().replace("box = [0.8, 0.8]", "box = [0.4, 0.8]") \
                .replace("count = 300", "count = 150")
        with open(narrow, "w") as f:
            f.write(text)
        for scenario, ranks, words in ((narrow, 4, ["narrow.toml", "mpirun -n", "will grow",
                                                    "too thin"]),):
            r = run(ranks, scenario, os.path.join(tmp, os.path.basename(scenario) + ".out"))
            check(r.returncode == 2 and all(w in r.stderr for w in words) and
                  r.stderr.count("error:") == 1,
                  f"{os.path.basename(scenario)} on {ranks} ranks refused: exit {r.returncode}, "
                  f"{r.stderr.strip()}")
    print(f"{len(failures)} failures" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
