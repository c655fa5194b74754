#!/usr/bin/env python3
"""Pools the runs of several refinement folders of one anchor (refine_L.sh's output, e.g.
runs/refine/L_silt and runs/refine46/L_silt) by grain size: T_max per seed, mean, standard
deviation and cv of all the seeds, and the change of the mean from the largest grains to
each smaller size with its standard error.

usage: pool_seeds.py FOLDER [FOLDER ...]
"""
import csv
import math
import sys
from pathlib import Path


def mean_std(values):
    n = len(values)
    m = sum(values) / n
    s = math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1)) if n > 1 else 0.0
    return m, s


def main(folders):
    runs = {}
    for folder in folders:
        with open(Path(folder) / "pullout_runs.csv", newline="") as f:
            for r in csv.DictReader(f):
                key = float(r["radius_factor"])
                runs.setdefault(key, {})[int(r["seed"])] = (float(r["T_max"]) / 1e3, int(r["slippage"]))
    if not runs:
        sys.exit("no runs")
    sizes = sorted(runs, reverse=True)
    full = mean_std([t for t, _ in runs[sizes[0]].values()])
    n_full = len(runs[sizes[0]])
    print("| radius factor | seeds | T_max per seed (kN/m) | mean +- std | cv | slippage runs | change of the mean | its standard error |")
    print("| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: |")
    for size in sizes:
        seeds = runs[size]
        values = [seeds[k][0] for k in sorted(seeds)]
        m, s = mean_std(values)
        change = se = ""
        if size != sizes[0]:
            change = f"{100 * (m / full[0] - 1):+.1f} %"
            se = f"{100 * math.sqrt(full[1] ** 2 / n_full + s ** 2 / len(values)) / full[0]:.1f} %"
        print(f"| {size:g} | {len(values)} | {', '.join(f'{v:.2f}' for v in values)} | "
              f"{m:.2f} +- {s:.2f} | {100 * s / m:.0f} % | {sum(seeds[k][1] for k in seeds)} | {change} | {se} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
