#!/usr/bin/env python3
"""Where the tension goes: sheet_parts_table.py RUN_DIR... (each the output folder of a
pull-out run over seeds, e.g. runs/pullout2d/L_silt; a refinement's folders with
--size F, e.g. --size 1 runs/refine/L_silt+runs/refine46/L_silt: the runs at radius factor F
of the folders joined by "+", pooled). For each, the tension each part of
the sheet takes off (run-out, bend, trench part), the grains' normal force on it and the
friction it mobilises (carried / normal), as mean +- standard deviation over the seeds at
T_max and when the pull starts, beside the slippage estimate's own terms (F1, the capstan
factor's share, F2). Prints the markdown table of docs/anchorage_design.md.
"""
import json
import statistics
import sys
from pathlib import Path

PARTS = ["runout", "bend", "trench"]


def spread(values, scale=1.0, digits=1):
    v = [x / scale for x in values]
    sd = statistics.stdev(v) if len(v) > 1 else 0.0
    return f"{statistics.mean(v):.{digits}f} +- {sd:.{digits}f}"


def table(folders, size=None):
    pattern = f"size{size}_seed*/summary.json" if size else "seed*/summary.json"
    runs = [p for f in folders for p in sorted((f / "runs").glob(pattern))]
    res = [json.loads(p.read_text())["results"] for p in runs]
    name = folders[0].name
    est = res[0]["sheet_parts"]["slip_estimate"]
    print(f"| `{name}` ({len(res)} seeds) | carried (kN/m) | normal force (kN/m) |"
          " mobilised carried / normal | tension ratio across the bend |")
    print("| --- | ---: | ---: | ---: | ---: |")
    for when in ("at_start", "at_T_max"):
        for part in PARTS:
            rows = [r["sheet_parts"][when][part] for r in res]
            ratio = (spread([x["tension_ratio"] for x in rows], digits=2)
                     if part == "bend" else "")
            print(f"| {part}, {when.replace('_', ' ')} | {spread([x['carried'] for x in rows], 1e3)}"
                  f" | {spread([x['normal'] for x in rows], 1e3)}"
                  f" | {spread([x['mobilised'] for x in rows], digits=2)} | {ratio} |")
    for part in PARTS:
        e = est[part]
        normal = f"{e['normal'] / 1e3:.1f}" if "normal" in e else ""
        mob = f"{e['mobilised']:.2f}" if "mobilised" in e else ""
        ratio = f"{e['tension_ratio']:.2f}" if part == "bend" else ""
        print(f"| {part}, slippage estimate | {e['carried'] / 1e3:.1f} | {normal} | {mob} |"
              f" {ratio} |")
    tmax = [r["T_max"] for r in res]
    print(f"\nT_max {spread(tmax, 1e3, 2)} kN/m over {len(res)} seeds"
          f" ({', '.join(f'{t / 1e3:.2f}' for t in tmax)}); T_analytic_slip"
          f" {res[0]['T_analytic_slip'] / 1e3:.2f} kN/m\n")


if __name__ == "__main__":
    args = sys.argv[1:]
    size = None
    if args[:1] == ["--size"]:
        size, args = args[1], args[2:]
    for arg in args:
        table([Path(a) for a in arg.split("+")], size)
