#!/usr/bin/env python3
"""Run-out anchors against the analytic slippage estimate: runout_study.py [OUT_DIR].

Runs runout_base.toml for several run-out lengths and covers (geodem run --set ...), and
prints the table of docs/lab_tests.md: T_max, T_analytic_slip, their ratio, and the mean
displacement of the anchoring soil (small: the sheet slips). Needs the built geodem in
build/ (run from the repository root). Writes OUT_DIR/runout_study.csv.
"""
import csv
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BASE = Path(__file__).resolve().parent / "runout_base.toml"
CASES = [(0.3, 0.1), (0.5, 0.1), (0.7, 0.1), (0.5, 0.06), (0.5, 0.15)]  # (length, cover) m


def main(argv):
    out = Path(argv[1] if len(argv) > 1 else "runs/runout_study")
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for length, cover in CASES:
        run_dir = out / f"L{length}_h{cover}"
        t0 = time.time()
        subprocess.run([str(ROOT / "build" / "geodem"), "run", str(BASE), "--out", str(run_dir),
                        "--overwrite", "--quiet", "--set", f"soil.deposit_cache={out / 'deposits'}", "--set", f"anchor.runout_length={length}",
                        "--set", f"anchor.cover={cover}", "--set", "output.vtk=false",
                        "--set", "output.plots=false"], check=True)
        r = json.loads((run_dir / "summary.json").read_text())["results"]
        rows.append({"runout_length": length, "cover": cover, "grains": r["grains"],
                     "T_max": r["T_max"], "T_analytic_slip": r["T_analytic_slip"],
                     "ratio": r["T_max"] / r["T_analytic_slip"],
                     "soil_displacement_mm": 1e3 * r["soil_displacement_mean"],
                     "wall_s": time.time() - t0})
    with open(out / "runout_study.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("| run-out L (m) | cover (m) | grains | T_max (N/m) | T_analytic_slip (N/m) | ratio |"
          " soil displacement (mm) | wall time (s) |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in rows:
        print(f"| {r['runout_length']} | {r['cover']} | {r['grains']} | {r['T_max']:.0f} |"
              f" {r['T_analytic_slip']:.0f} | {r['ratio']:.2f} | {r['soil_displacement_mm']:.1f} |"
              f" {r['wall_s']:.0f} |")


if __name__ == "__main__":
    main(sys.argv)
