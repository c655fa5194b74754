#!/usr/bin/env python3
"""The table of examples/pullout2d/README.md from the runs of refresh_expected.sh:
pullout_table.py OUT_DIR. Each example's T_max as mean +- standard deviation over its
seeds (and the coefficient of variation), the design estimates, the mechanism the runs
show and the one the design methods predict, grains and wall time per run.
"""
import json
import sys
from pathlib import Path

NAMES = ["L_sand", "L_silt", "V_sand", "runout_sand", "runout_silt"]


def main(argv):
    out = Path(argv[1] if len(argv) > 1 else "runs/pullout2d")
    print("| example | seeds | T_max (kN/m), mean +- std | cv | T_analytic_slip | T_analytic_soil |"
          " T_max / T_design | mechanism (runs) | design mechanism | soil displacement /"
          " pull at T_max | grains | wall time per run (s) |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- | ---: | ---: | ---: |")
    for name in NAMES:
        path = out / name / "summary.json"
        if not path.is_file():
            continue
        s = json.loads(path.read_text())
        g = s["results"]["groups"][0]
        runs = [json.loads((out / name / "runs" / r / "summary.json").read_text())
                for r in g["runs"]]
        design = [r["results"]["design_mechanism"] for r in runs]
        # (rounded first, so that a median a hair below zero prints as 0.000, not -0.000)
        ratio = [round(r["results"]["mechanism_measures"]["soil_ratio"], 3) + 0.0 for r in runs]
        t, slip, soil = g["T_max"], g["T_analytic_slip"], g["T_analytic_soil"]
        mech = ", ".join(f"{v} {k}" for k, v in sorted(g["mechanisms"].items()))
        print(f"| `{name}` | {t['count']} | {t['mean'] / 1e3:.1f} +- {t['std'] / 1e3:.1f} |"
              f" {100 * t['cv']:.0f} % | {slip['mean'] / 1e3:.1f} | {soil['mean'] / 1e3:.1f} |"
              f" {g['T_max_over_design']:.2f} | {mech} | {design[0]} |"
              f" {min(ratio):.3f} to {max(ratio):.3f} | {g['grains']['mean']:,.0f} |"
              f" {g['wall_s']['mean']:.0f} |")


if __name__ == "__main__":
    main(sys.argv)
