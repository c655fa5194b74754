#!/usr/bin/env python3
"""Robustness sweep: every lab kind, small, over many seeds; no run may fail.

    tests/robustness/seed_sweep.py GEODEM [--seeds 200] [--jobs 2] [--kinds "a;b"]

Each case is a small scenario run with seed = 1 .. N (`--set seed=K`); a run fails when
geodem exits with anything but 0. Prints a table (kind, seeds, failures, run time) and each
failure's message; exits 1 on any failure. The table is in docs/verification.md.
"""
import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

BIAXIAL = """
kind = "triaxial"
dimension = {dim}
seed = 1
[sample]
box = {box}
count = {count}
initial_porosity = 0.9
{grain}
[material]
density = 2650.0
young = 1e8
kt_over_kn = 0.5
friction = 0.5
rolling_friction = {rolling}
normal_cohesion = {cohesion}
shear_cohesion = {cohesion}
[compaction]
confining_stress = 1e5
{target}
[shear]
strain_rate = 0.05
max_axial_strain = 0.02
confining_stress = [5e4, 1e5]
[output]
plots = false
vtk = false
"""

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "cli"))
from small_scenarios import SMALL_PULLOUT  # noqa: E402

# The small run-out box of the command-line tests, smaller still (about 300 discs).
PULLOUT = (SMALL_PULLOUT.replace("length = 0.8", "length = 0.6")
           .replace("foundation = 0.12", "foundation = 0.08")
           .replace("runout_length = 0.5", "runout_length = 0.35")
           .replace("cover = 0.1", "cover = 0.06")
           .replace("max_displacement = 0.03", "max_displacement = 0.01")
           + "[output]\nplots = false\nvtk = false\n")


def biaxial(dim=2, count=100, grain="", rolling=0.0, cohesion=0.0, target=""):
    box = "[0.4, 0.8]" if dim == 2 else "[0.02, 0.02, 0.04]"
    return BIAXIAL.format(dim=dim, box=box, count=count, grain=grain, rolling=rolling,
                          cohesion=cohesion, target=target)


CASES = {
    "biaxial 2D discs": biaxial(),
    "biaxial 2D clumps, rolling, friction reduction": biaxial(
        grain='grain = "pair_0.9"', rolling=0.1, target="target_porosity = 0.235"),
    "biaxial 2D clumps, bonds": biaxial(grain='grain = "pair_0.9"', cohesion=5e4),
    "triaxial 3D spheres": biaxial(dim=3, count=150).replace("max_axial_strain = 0.02",
                                                            "max_axial_strain = 0.01"),
    "triaxial 3D clumps, rolling": biaxial(dim=3, count=80, grain='grain = "pair_0.9"',
                                           rolling=0.1).replace(
        "initial_porosity = 0.9", "initial_porosity = 0.95").replace(
        "max_axial_strain = 0.02", "max_axial_strain = 0.01"),
    "pull-out 2D run-out": PULLOUT.format(shape="runout", trench=""),
    "pull-out 2D L, clumps": PULLOUT.format(
        shape="L", trench="trench_depth = 0.04\ntrench_width = 0.06").replace(
        "radius_fuzz = 0.25", 'radius_fuzz = 0.25\ngrain = "pair_0.9"'),
}


def run_one(geodem, scenario, seed, work):
    out = work / f"s{seed}"
    t0 = time.monotonic()
    r = subprocess.run([geodem, "run", str(scenario), "--out", str(out), "--quiet",
                        "--threads", "1", "--set", f"seed={seed}"],
                       capture_output=True, text=True, timeout=1800)
    return seed, r.returncode, r.stderr.strip().splitlines()[-1:] or [""], time.monotonic() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("geodem")
    ap.add_argument("--seeds", type=int, default=200)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--kinds", help="names of CASES, separated by ';' (default: all)")
    a = ap.parse_args()
    geodem = str(Path(a.geodem).resolve())
    names = a.kinds.split(";") if a.kinds else list(CASES)
    print("| case | seeds | failures | run time (s), median (max) |")
    print("| --- | ---: | ---: | ---: |")
    failures = []
    for name in names:
        with tempfile.TemporaryDirectory() as tmp:
            work = Path(tmp)
            scenario = work / "scenario.toml"
            scenario.write_text(CASES[name])
            with ThreadPoolExecutor(a.jobs) as pool:
                results = list(pool.map(lambda s: run_one(geodem, scenario, s, work),
                                        range(1, a.seeds + 1)))
        bad = [(s, rc, msg[0]) for s, rc, msg, _ in results if rc != 0]
        times = [t for *_, t in results]
        print(f"| {name} | {a.seeds} | {len(bad)} | {statistics.median(times):.1f}"
              f" ({max(times):.1f}) |", flush=True)
        failures += [f"{name}, seed {s}: exit {rc}: {m}" for s, rc, m in bad]
    for f in failures:
        print("FAILED", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
