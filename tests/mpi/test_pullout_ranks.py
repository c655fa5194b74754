#!/usr/bin/env python3
"""`mpirun -n K geodem run pullout.toml` spreads one pull-out test over K ranks with the same
bits for any K: an L-shaped anchor in a bonded soil (tests/mpi/pullout_kind2d.toml: layers
deposited, trimmed and excavated, the sheet laid with its inertia scaled, a free front whose
spilled grains are removed, a surcharge plate, bonds, then the pull) on 1 rank and on 2 ranks of
2 threads (the first run of a pull-out over seeds in groups of 2 ranks) writes the same
history.csv, preparation.csv, tension_profiles.csv, grain and sheet states and results. Killed by
SIGKILL on 2 ranks and resumed on 4, or stopped by SIGTERM on 2 ranks and resumed by one
process without mpirun, it writes the files of the uninterrupted run, its last VTK frame in one
piece per rank holding every grain once. A deposit cache stored by a run on 2 ranks is loaded by
runs on 4 ranks and on 1, which write the files of the run without a cache.

    test_pullout_ranks.py PATH/TO/geodem
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
SCENARIO = os.path.join(HERE, "pullout_kind2d.toml")
FILES = ("preparation.csv", "tension_profiles.csv", "states/grains_initial.csv",
         "states/grains_final.csv", "states/sheet_final.csv")


def outputs(out):
    """What two runs of one test must share."""
    got = {"history": history(os.path.join(out, "history.csv")),
           "results": json.load(open(os.path.join(out, "summary.json")))["results"]}
    for name in FILES:
        got[name] = open(os.path.join(out, name)).read()
    return got


def final_ids(got):
    """The ids of the grains of the final state file (`outputs`)."""
    return [int(float(line.split(",")[0]))
            for line in got["states/grains_final.csv"].splitlines()[1:]]


def main() -> int:
    geodem = sys.argv[1]
    launch = mpi_launch(geodem)
    if launch is None:
        return 77
    mpirun, env = launch

    def run(ranks, out, *extra, threads=1):
        launcher = [mpirun, "-n", str(ranks)] if ranks else []
        args = launcher + [geodem, "run", SCENARIO, "--out", out, "--quiet", "--threads",
                           str(threads)] + list(extra)
        return subprocess.run(args, env=env, text=True, capture_output=True, timeout=600)

    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "pullout.1")
        r = run(1, out)
        ref = outputs(out) if r.returncode == 0 else None
        if ref is None:
            check(False, f"the pull-out on 1 rank ran: {r.stdout}{r.stderr}")
        else:
            res, prep = ref["results"], ref["results"]["preparation"]
            timing = json.load(open(os.path.join(out, "summary.json")))["timing"]
            final = final_ids(ref)
            check(timing["ranks"] == 1 and timing["particles"] == res["grains"] == len(final) and
                  prep["bonds"] > 0 and prep["spilled_grains"] > 0 and res["T_max"] > 0.0 and
                  len(ref["history"]) > 10,
                  f"the pull-out on 1 rank: {res['grains']} grains ({prep['spilled_grains']} "
                  f"spilled off the free front), {prep['bonds']} bonds, T_max "
                  f"{res['T_max']:.1f} N/m, {len(ref['history']) - 1} history rows")

        # Over seeds in groups of 2 ranks of 2 threads (--ranks-per-run 2): the run of the
        # scenario's seed has the bits of the run on 1 rank.
        out = os.path.join(tmp, "series")
        r = run(2, out, "--set", "seeds=2", "--ranks-per-run", "2", threads=2)
        run_dir = os.path.join(out, "runs", "seed3")
        if r.returncode != 0 or ref is None:
            check(False, f"the pull-out over 2 seeds in a group of 2 ranks ran: {r.stderr}")
        else:
            got = outputs(run_dir)
            for part in got:
                check(got[part] == ref[part], f"{part} on 2 ranks the same as on 1 rank")

        # Killed, then resumed on another number of ranks: the files of the uninterrupted run.
        # SIGKILL leaves the last periodic checkpoint (here in the settle of the bonded soil);
        # SIGTERM stops every rank at a step they agree on (here in the trench's fill).
        for first, then, sig, at in ((2, 4, signal.SIGKILL, 95000),
                                     (2, 0, signal.SIGTERM, 40000)):
            out = os.path.join(tmp, f"pullout.{sig.name}")
            args = [mpirun, "-n", str(first), geodem, "run", SCENARIO, "--out", out, "--quiet",
                    "--set", "checkpoint.every_steps=5000"]
            ck = stop_at_checkpoint(args, env, out, at, sig)
            if ck is None:
                check(False, f"the pull-out on {first} ranks ended before it was stopped")
                continue
            launcher = [mpirun, "-n", str(then)] if then else []
            r = subprocess.run(launcher + [geodem, "run", SCENARIO, "--resume", out, "--quiet",
                                           "--set", "checkpoint.every_steps=5000"],
                               env=env, text=True, capture_output=True, timeout=600)
            same = r.returncode == 0 and ref is not None and outputs(out) == ref
            check(same, f"{sig.name} on {first} ranks (checkpoints {ck[-1:]}), resumed on "
                        f"{then or 'one process without mpirun'}: every file of the "
                        f"uninterrupted run {'' if r.returncode == 0 else r.stderr}")
            if same:
                count, ids = pieces(out)
                final = final_ids(ref)
                check(count == max(then, 1) and sorted(ids) == final,
                      f"its last VTK frame in {count} pieces holding every grain once")

        # A deposit cache: the foundation stored by a run on 2 ranks (gathered whole with its
        # domain's keys and contact history), loaded by runs on 4 ranks and on 1; each writes
        # every file of the run without a cache, the preparation's note of the cache aside.
        cache = os.path.join(tmp, "cache")
        notes = []
        for ranks in (2, 4, 1):
            out = os.path.join(tmp, f"cached.{ranks}")
            r = run(ranks, out, "--set", f'soil.deposit_cache="{cache}"')
            if r.returncode != 0 or ref is None:
                check(False, f"with a deposit cache on {ranks} ranks: {r.stderr}")
                continue
            got = outputs(out)
            notes.append(got["results"]["preparation"].pop("deposit_cache", "").split(" ")[0])
            for part in got:
                check(got[part] == ref[part],
                      f"{part} with a deposit cache on {ranks} ranks ({notes[-1]}) the same as "
                      f"without one")
        stored = os.listdir(cache) if os.path.isdir(cache) else []
        check(notes == ["stored", "loaded", "loaded"] and len(stored) == 1 and
              stored[0].startswith("pullout_foundation_ranks_"),
              f"the cache stored once, by the first run ({stored}), loaded by the others ({notes})")

    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
