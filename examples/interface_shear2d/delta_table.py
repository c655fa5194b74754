#!/usr/bin/env python3
"""Macroscopic interface friction against the sheet's local friction, both soils:
delta_table.py [OUT_DIR] [--seeds N].

Runs sand.toml and silt.toml (the sheet pulled out between two layers of soil) for local
interface frictions of 15 to 45 deg over N seeds (default 3), and sand.toml on the rigid
base for one seed, two runs side by side, one thread each; prints the table of
docs/anchorage_design.md (peak envelope friction and adhesion, mean and spread over the
seeds) and writes OUT_DIR/delta_table.csv. Needs the built geodem in build/ (run from
the repository root).
"""
import csv
import json
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
DELTAS = [15.0, 20.0, 25.0, 30.0, 34.0, 40.0, 45.0]


def run(case):
    soil, base, delta, seed, out = case
    run_dir = out / f"{soil}_{base}_d{delta:g}_s{seed}"
    if not (run_dir / "summary.json").is_file():
        subprocess.run([str(ROOT / "build" / "geodem"), "run", str(HERE / f"{soil}.toml"),
                        "--out", str(run_dir), "--overwrite", "--quiet", "--threads", "1",
                        "--set", f"sheet.interface_friction_deg={delta}",
                        "--set", f"seed={seed}", "--set", f'box.base="{base}"',
                        "--set", "output.vtk=false", "--set", "output.plots=false"],
                       check=True)
    s = json.loads((run_dir / "summary.json").read_text())
    r = s["results"]
    return {"soil": soil, "base": base, "local_deg": delta, "seed": seed,
            "macro_deg": r["interface_friction_peak_deg"],
            "adhesion_kPa": r["interface_adhesion_peak"] / 1e3,
            "residual_deg": r["interface_friction_residual_deg"],
            "wall_s": s["timing"]["wall_s"]}


def main(argv):
    seeds = 3
    if "--seeds" in argv:
        k = argv.index("--seeds")
        seeds = int(argv[k + 1])
        argv = argv[:k] + argv[k + 2:]
    out = Path(argv[1] if len(argv) > 1 else "runs/delta_table")
    out.mkdir(parents=True, exist_ok=True)
    cases = [(soil, "soil", d, s, out) for soil in ("sand", "silt") for d in DELTAS
             for s in range(1, seeds + 1)]
    cases += [("sand", "rigid", d, 1, out) for d in DELTAS]
    t0 = time.time()
    with ThreadPoolExecutor(max_workers=2) as pool:
        rows = list(pool.map(run, cases))
    with open(out / "delta_table.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)

    def cell(soil, base, d, key):
        v = [r[key] for r in rows if (r["soil"], r["base"], r["local_deg"]) == (soil, base, d)]
        if len(v) > 1:
            return f"{statistics.mean(v):.1f} +- {statistics.stdev(v):.1f}"
        return f"{v[0]:.2f}"

    print(f"| local delta (deg) | sand: macro (deg) | sand: adhesion (kPa) | silt: macro (deg) |"
          f" silt: adhesion (kPa) | sand on a rigid base: macro (deg) |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    for d in DELTAS:
        print(f"| {d:g} | {cell('sand', 'soil', d, 'macro_deg')} |"
              f" {cell('sand', 'soil', d, 'adhesion_kPa')} | {cell('silt', 'soil', d, 'macro_deg')} |"
              f" {cell('silt', 'soil', d, 'adhesion_kPa')} | {cell('sand', 'rigid', d, 'macro_deg')} |")
    print(f"({seeds} seeds on the soil base; {len(rows)} runs of"
          f" {min(r['wall_s'] for r in rows):.0f}-{max(r['wall_s'] for r in rows):.0f} s each,"
          f" two side by side; this invocation took {time.time() - t0:.0f} s)")


if __name__ == "__main__":
    main(sys.argv)
