#!/usr/bin/env python3
"""`mpirun -n K geodem run interface_shear.toml` spreads one interface shear test over K ranks
with the same bits for any K: a sheet pulled out between two layers of bonded pair clumps
(tests/mpi/interface_shear2d.toml: the lower layer held while the sheet is laid and the upper
one deposited; two normal stresses, each test from a copy of the deposit and its domain) and
the same soil sheared over a rigid base, on 1 rank and on 2 ranks (2 threads each for the
first), write the same history.csv and results, the last VTK frame in one piece per rank
holding every grain once. SIGTERM on 2 ranks stops both with an "interrupted" summary. A deposit
cache stored by a run on 2 ranks is loaded by runs on 4 ranks and on 1, which give the results of
the run without a cache.

    test_interface_ranks.py PATH/TO/geodem
Exit 77 (skipped) without mpirun or without MPI in geodem.
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

from test_scene_ranks import check, failures, history, mpi_launch, pieces, signal_run

HERE = os.path.dirname(os.path.abspath(__file__))


def outputs(out):
    """What two runs of one test must share."""
    return {"history": history(os.path.join(out, "history.csv")),
            "results": json.load(open(os.path.join(out, "summary.json")))["results"]}


def main() -> int:
    geodem = sys.argv[1]
    launch = mpi_launch(geodem)
    if launch is None:
        return 77
    mpirun, env = launch

    def args(ranks, scenario, out, *extra, threads=1):
        return [mpirun, "-n", str(ranks), geodem, "run", scenario, "--out", out, "--quiet",
                "--threads", str(threads)] + list(extra)

    with tempfile.TemporaryDirectory() as tmp:
        soil = os.path.join(HERE, "interface_shear2d.toml")
        rigid = os.path.join(tmp, "rigid.toml")
        with open(soil) as f:
            text = f.read()
        with open(rigid, "w") as f:
            f.write(text.replace('base = "soil"\nlower_height = 0.05\n', 'base = "rigid"\n'))
        for name, scenario in (("soil base", soil), ("rigid base", rigid)):
            got = []
            for ranks in (1, 2):
                out = os.path.join(tmp, f"{name[:4]}.{ranks}")
                threads = 2 if ranks == 2 and scenario == soil else 1
                r = subprocess.run(args(ranks, scenario, out, threads=threads), env=env,
                                   text=True, capture_output=True, timeout=600)
                if r.returncode != 0:
                    check(False, f"{name} on {ranks} ranks ran: {r.stdout}{r.stderr}")
                    break
                got.append(outputs(out))
                res = got[-1]["results"]
                timing = json.load(open(os.path.join(out, "summary.json")))["timing"]
                count, ids = pieces(out)
                grains = res["tests"][-1]["grains"]
                check(timing["ranks"] == ranks and timing["particles"] == grains and
                      len(res["tests"]) == 2 and all(t["bonds"] > 0 for t in res["tests"]) and
                      count == ranks and len(ids) == len(set(ids)) == grains,
                      f"{name} on {ranks} ranks: {grains} grains, bonds "
                      f"{[t['bonds'] for t in res['tests']]}, interface friction "
                      f"{res['interface_friction_peak_deg']:.2f} deg, the last frame in {count} "
                      f"pieces holding every grain once")
            if len(got) == 2:
                rows = len(got[0]["history"]) - 1
                check(rows >= 50 and got[0] == got[1],
                      f"{name}: history ({rows} rows) and results on 2 ranks the same as on 1")

        # A signal stops every rank at a step they agree on; rank 0 says so in the summary. The
        # sheet is pulled ten times slower (about 14 s): the run itself takes about 3 s, and
        # finished before the signal came on a fast machine.
        out = os.path.join(tmp, "stopped")
        p = subprocess.Popen(args(2, soil, out, "--set", "shear.rate=0.002"), env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        time.sleep(3.0)
        signal_run(out, signal.SIGTERM)
        _, err = p.communicate(timeout=120)
        summary = os.path.join(out, "summary.json")
        status = json.load(open(summary))["status"] if os.path.exists(summary) else None
        check(p.returncode != 0 and status == "interrupted",
              f"SIGTERM on 2 ranks: exit {p.returncode}, summary {status}")

        # A deposit cache: stored by a run on 2 ranks (the whole deposit with its domain's keys
        # and contact history), loaded by runs on 4 ranks and on 1; every run gives the results
        # of the run without a cache (the soil base's, above), the cache's note aside.
        cache = os.path.join(tmp, "cache")
        ref_out = os.path.join(tmp, "soil.1")
        soil_ref = (outputs(ref_out) if os.path.exists(os.path.join(ref_out, "summary.json"))
                    else None)
        notes = []
        for ranks in (2, 4, 1):
            out = os.path.join(tmp, f"cached.{ranks}")
            r = subprocess.run(args(ranks, soil, out, "--set", f'soil.deposit_cache="{cache}"'),
                               env=env, text=True, capture_output=True, timeout=600)
            if r.returncode != 0 or soil_ref is None:
                check(False, f"with a deposit cache on {ranks} ranks: {r.stderr}")
                continue
            cached = outputs(out)
            notes.append(cached["results"].pop("deposit_cache", "").split(" ")[0])
            check(cached == soil_ref,
                  f"with a deposit cache on {ranks} ranks ({notes[-1]}): the history and results "
                  f"of the run without one")
        stored = [f for f in os.listdir(cache)] if os.path.isdir(cache) else []
        check(notes == ["stored", "loaded", "loaded"] and len(stored) == 1 and
              stored[0].startswith("interface_shear_deposit_ranks_"),
              f"the cache stored once, by the first run ({stored}), loaded by the others ({notes})")

    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
