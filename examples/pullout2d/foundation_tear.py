#!/usr/bin/env python3
"""Whether a pull-out run tore the bonded foundation in front of the trench's edge, from
its states/grains_{initial,final}.csv and states/sheet_{initial,final}.csv (the start and
the end of the pull). For each run folder: how far the foundation under the run-out's last
0.3 m before the rounded edge (down to 6 cm below the run-out level) moved along the pull
(negative x is towards the pull) and up; how far the cover above the run-out (x 0.3-0.8 m,
5 cm and more above the sheet) and the sheet itself there rose. The geometry comes from the
run's scenario.toml (box.foundation, anchor.runout_length, anchor.edge_radius).

usage: foundation_tear.py RUN_FOLDER [RUN_FOLDER ...]
(e.g. runs/refine/L_silt/runs/size0.5_seed*)
"""
import csv
import sys
import tomllib
from pathlib import Path
from statistics import median


def read_xy(path, key):
    with open(path, newline="") as f:
        return {r[key]: (float(r["x"]), float(r["y"])) for r in csv.DictReader(f)}


def report(folder):
    run = Path(folder)
    sc = tomllib.loads((run / "scenario.toml").read_text())
    level = sc["box"]["foundation"]
    edge = sc["anchor"]["runout_length"] - sc["anchor"].get("edge_radius", 0.0)
    g0 = read_xy(run / "states" / "grains_initial.csv", "id")
    g1 = read_xy(run / "states" / "grains_final.csv", "id")
    s0 = read_xy(run / "states" / "sheet_initial.csv", "node")
    s1 = read_xy(run / "states" / "sheet_final.csv", "node")
    found, cover = [], []
    for i, (x, y) in g0.items():
        if i not in g1:
            continue
        d = (1e3 * (g1[i][0] - x), 1e3 * (g1[i][1] - y))
        if edge - 0.3 < x < edge and level - 0.06 < y < level:
            found.append(d)
        elif 0.3 < x < 0.8 and y > level + 0.05:
            cover.append(d)
    sheet = [1e3 * (s1[n][1] - y) for n, (x, y) in s0.items() if 0.3 < x < 0.8 and abs(y - level) < 0.02]
    dx = [d[0] for d in found]
    print(f"{folder}: foundation in front of the edge, along the pull {min(dx):.1f} mm at most, "
          f"median {median(dx):.1f} mm, rise median {median(d[1] for d in found):.1f} mm "
          f"({len(found)} grains); cover over the run-out rise median {median(d[1] for d in cover):.1f} mm; "
          f"sheet rise median {median(sheet):.1f} mm")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for f in sys.argv[1:]:
        report(f)
