#!/usr/bin/env python3
"""Pools the runs of several refinement folders of one anchor (refine_L.sh's output, e.g.
runs/refine/L_silt and runs/refine46/L_silt) by grain size: T_max per seed, mean, standard
deviation and cv of all the seeds, and the change of the mean from the largest grains to
each smaller size with its standard error.

A second table gives the sliding tension: the mean tension over the late part of the pull
(default from 100 mm to the end, --window FROM TO in metres), read from each run's history.csv, and the
sheet's parts' mean normal forces over the same window (run-out, bend, trench). A peak can
be a short jam; the sliding tension is what the interface holds while it slides. For
refine_L.sh's 200 mm pulls the default window is the runs' own T_residual (the pull's
second half, its last row a hair past 200 mm included).

usage: pool_seeds.py [--window FROM TO] FOLDER [FOLDER ...]
"""
import argparse
import csv
import math
from pathlib import Path

PARTS = ("runout_normal", "bend_normal", "trench_normal")


def mean_std(values):
    n = len(values)
    m = sum(values) / n
    s = math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1)) if n > 1 else 0.0
    return m, s


def window_means(history, lo, hi):
    """Mean tension and parts' normal forces (kN/m) over the pull's window [lo, hi] (m)."""
    with open(history, newline="") as f:
        rows = [r for r in csv.DictReader(f) if lo <= float(r["displacement"]) <= hi]
    if not rows:
        return None
    return [sum(float(r[k]) for r in rows) / len(rows) / 1e3 for k in ("tension", *PARTS)]


def read_runs(folders, lo, hi):
    runs = {}
    for folder in folders:
        with open(Path(folder) / "pullout_runs.csv", newline="") as f:
            for r in csv.DictReader(f):
                factor, seed = float(r["radius_factor"]), int(r["seed"])
                history = Path(folder) / "runs" / f"size{r['radius_factor']}_seed{seed}" / "history.csv"
                late = window_means(history, lo, hi) if history.exists() else None
                runs.setdefault(factor, {})[seed] = (float(r["T_max"]) / 1e3, int(r["slippage"]), late)
    return runs


def change_columns(m, s, n, full, n_full):
    se = math.sqrt(full[1] ** 2 / n_full + s ** 2 / n) / full[0]
    return f"{100 * (m / full[0] - 1):+.1f} %", f"{100 * se:.1f} %"


def peak_table(runs, sizes):
    full_values = [t for t, _, _ in runs[sizes[0]].values()]
    full = mean_std(full_values)
    print("| radius factor | seeds | T_max per seed (kN/m) | mean +- std | cv | slippage runs | change of the mean | its standard error |")
    print("| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: |")
    for size in sizes:
        seeds = runs[size]
        values = [seeds[k][0] for k in sorted(seeds)]
        m, s = mean_std(values)
        change = se = ""
        if size != sizes[0]:
            change, se = change_columns(m, s, len(values), full, len(full_values))
        print(f"| {size:g} | {len(values)} | {', '.join(f'{v:.2f}' for v in values)} | "
              f"{m:.2f} +- {s:.2f} | {100 * s / m:.0f} % | {sum(seeds[k][1] for k in seeds)} | {change} | {se} |")


def sliding_table(runs, sizes, lo, hi):
    def late(size):
        return {k: v[2] for k, v in sorted(runs[size].items()) if v[2] is not None}

    if not late(sizes[0]):
        return
    full_values = [v[0] for v in late(sizes[0]).values()]
    full = mean_std(full_values)
    print()
    to = "the end" if math.isinf(hi) else f"{1e3 * hi:.0f} mm"
    print(f"Sliding tension: means from {1e3 * lo:.0f} mm of pull to {to} (kN/m)")
    print()
    print("| radius factor | seeds | tension per seed | mean +- std | cv | change of the mean | its standard error | normal force: run-out, bend, trench (means) |")
    print("| ---: | ---: | --- | ---: | ---: | ---: | ---: | --- |")
    for size in sizes:
        seeds = late(size)
        if not seeds:
            continue
        values = [v[0] for v in seeds.values()]
        m, s = mean_std(values)
        change = se = ""
        if size != sizes[0]:
            change, se = change_columns(m, s, len(values), full, len(full_values))
        parts = [sum(v[1 + j] for v in seeds.values()) / len(seeds) for j in range(len(PARTS))]
        print(f"| {size:g} | {len(values)} | {', '.join(f'{v:.2f}' for v in values)} | {m:.2f} +- {s:.2f} | "
              f"{100 * s / m:.0f} % | {change} | {se} | {', '.join(f'{p:.1f}' for p in parts)} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--window", type=float, nargs=2, default=[0.1, math.inf], metavar=("FROM", "TO"))
    ap.add_argument("folders", nargs="+")
    a = ap.parse_args()
    runs = read_runs(a.folders, *a.window)
    if not runs:
        raise SystemExit("no runs")
    sizes = sorted(runs, reverse=True)
    peak_table(runs, sizes)
    sliding_table(runs, sizes, *a.window)


if __name__ == "__main__":
    main()
