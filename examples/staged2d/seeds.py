#!/usr/bin/env python3
"""Runs the staged example with seeds 1, 2 and 3 and prints the table of its README
(mean and spread of each figure over the seeds).

    examples/staged2d/seeds.py [GEODEM] [OUT]     (defaults: build/geodem, runs/staged2d)
"""
import json
import statistics
import subprocess
import sys
from pathlib import Path

here = Path(__file__).resolve().parent
geodem = sys.argv[1] if len(sys.argv) > 1 else str(here.parents[1] / "build" / "geodem")
out = Path(sys.argv[2] if len(sys.argv) > 2 else "runs/staged2d")
rows = {}
for seed in (1, 2, 3):
    run = out / f"seed{seed}"
    subprocess.run([geodem, "run", str(here / "scenario.toml"), "--out", str(run), "--overwrite",
                    "--quiet", "--set", f"seed={seed}", "--set", "output.plots=false"], check=True)
    r = json.loads((run / "summary.json").read_text())["results"]
    st = {s["name"]: s for s in r["stages"]}
    figures = {
        "grains after excavation": r["particles"],
        "settle: time to rest (s)": st["settle"]["end_time"],
        "drop: time to rest (s)": st["drop"]["end_time"] - st["drop"]["start_time"],
        "load: time to rest (s)": st["load"]["end_time"] - st["load"]["start_time"],
        "plate stress at rest (kPa)": st["load"]["servos"][0]["stress"] / 1e3,
        "plate height at rest (mm)": st["load"]["walls"]["plate"]["point"][1] * 1e3,
        "floor normal force (N/m)": r["walls"]["floor"]["normal_force"],
        "fabric anisotropy at the end": r["fabric"]["anisotropy"],
    }
    for k, v in figures.items():
        rows.setdefault(k, []).append(v)
print("| figure | seed 1 | seed 2 | seed 3 | mean | standard deviation |")
print("| --- | ---: | ---: | ---: | ---: | ---: |")
for k, v in rows.items():
    cells = " | ".join(f"{x:.4g}" for x in v)
    print(f"| {k} | {cells} | {statistics.mean(v):.4g} | {statistics.stdev(v):.2g} |")
