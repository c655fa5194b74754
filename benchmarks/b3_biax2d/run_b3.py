#!/usr/bin/env python3
"""Benchmark B3: biaxial test of 8,000 discs and of 4,000 two-disc clumps (8,000 member
discs) to 15 % axial strain, one after the other, each timed as a whole process under
/usr/bin/time -v. Prints wall time, particle-steps per second (member discs), peak RSS and
the clump / disc cost ratio per particle-step. With --three-d: the same comparison on a 3D
triaxial test (4,000 spheres against 2,000 two-sphere clumps, to 15 %).

    benchmarks/b3_biax2d/run_b3.py [--out /tmp/b3] [--quick] [--three-d]
"""
import argparse
import json
import re
import subprocess
from pathlib import Path

HERE = Path(__file__).resolve().parent
GEODEM = HERE.parent.parent / "build" / "geodem"


def timed_run(scenario, out):
    out.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run(["/usr/bin/time", "-v", str(GEODEM), "run", str(scenario), "--out",
                           str(out / "run"), "--overwrite", "--quiet"], capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(proc.stderr)
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", proc.stderr)
    parts = [float(x) for x in wall.group(1).split(":")]
    wall_s = sum(p * 60 ** k for k, p in enumerate(reversed(parts)))
    s = json.loads((out / "run" / "summary.json").read_text())
    return wall_s, rss_kb / 1024, s


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="/tmp/b3")
    ap.add_argument("--quick", action="store_true", help="2,000 grains, 5 % strain")
    ap.add_argument("--three-d", action="store_true",
                    help="the 3D cost check instead: 4,000 spheres against 2,000 clumps")
    a = ap.parse_args()
    base = (HERE / ("triax3d_clumps.toml" if a.three_d else "biax2d.toml")).read_text()
    if a.quick:
        base = base.replace("count = 8000", "count = 2000").replace("box = [2.0, 4.0]",
                                                                    "box = [1.0, 2.0]")
        base = base.replace("max_axial_strain = 0.15", "max_axial_strain = 0.05")
    out = Path(a.out)
    rows = []
    round_name = "sphere" if a.three_d else "disc"
    for label, grain, count_factor in (("round", round_name, 1), ("two-member clumps", "pair_0.9", 2)):
        text = base.replace(f'grain = "{round_name}"', f'grain = "{grain}"')
        if count_factor == 2:
            text = re.sub(r"count = (\d+)", lambda m: f"count = {int(m.group(1)) // 2}", text)
        (out / grain).mkdir(parents=True, exist_ok=True)
        path = out / grain / "scenario.toml"
        path.write_text(text)
        wall, rss, s = timed_run(path, out / grain)
        t, r = s["timing"], s["results"]
        rows.append((label, r["grains"], t["particles"], t["steps"], wall,
                     t["particle_steps_per_s"], rss, r["porosity_initial"], r["phi_peak_deg"],
                     r["phi_residual_deg"]))
        print(f"{label}: grains {r['grains']}, members {t['particles']}, steps {t['steps']}, "
              f"wall {wall:.1f} s, {t['particle_steps_per_s'] / 1e6:.2f} M member-steps/s, "
              f"RSS {rss:.1f} MB, porosity {r['porosity_initial']:.3f}, "
              f"phi peak {r['phi_peak_deg']:.1f}, residual {r['phi_residual_deg']:.1f}",
              flush=True)
    ratio = rows[0][5] / rows[1][5]
    print(f"cost per member-step, clumps / round grains: {ratio:.2f}")


if __name__ == "__main__":
    main()
