#!/usr/bin/env python3
"""Confined dilatancy: cns_table.py OUT_DIR [STIFFNESSES...] runs the silt's interface shear
example (silt.toml) at constant normal stiffnesses (Pa/m; default 0, 1e7 and 5e7) and prints
the table of docs/anchorage_design.md ("Where the tension goes"): per test the normal stress
at the peak, the peak shear stress, its ratio to the initial normal stress and the plate's
largest rise, and the envelope on the normal stress at the peak. Run from the repository
root after scripts/build.sh; about 30 s.
"""
import json
import subprocess
import sys
from pathlib import Path


def main(argv):
    out = Path(argv[1] if len(argv) > 1 else "runs/interface_shear2d/cns")
    stiffnesses = [float(k) for k in argv[2:]] or [0.0, 1e7, 5e7]
    print("| K (MPa/m) | sigma0 (kPa) | sigma_n at the peak (kPa) | peak tau (kPa) |"
          " peak tau / sigma0 | rise (mm) | envelope on sigma_n at the peak |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | --- |")
    for k in stiffnesses:
        run_dir = out / f"k{k:g}"
        subprocess.run(["./build/geodem", "run", "examples/interface_shear2d/silt.toml", "--out",
                        str(run_dir), "--overwrite", "--quiet", "--set",
                        f"shear.normal_stiffness={k}"], check=True, stdout=subprocess.DEVNULL)
        r = json.loads((run_dir / "summary.json").read_text())["results"]
        t = r["tests"]

        def col(key, scale, digits):
            return " / ".join(f"{x[key] * scale:.{digits}f}" for x in t)
        ratio = " / ".join(f"{x['peak_shear_stress'] / x['normal_stress_target']:.2f}" for x in t)
        print(f"| {k / 1e6:g} | {col('normal_stress_target', 1e-3, 0)} |"
              f" {col('normal_stress_at_peak', 1e-3, 1)} | {col('peak_shear_stress', 1e-3, 2)} |"
              f" {ratio} | {col('dilation_max', 1e3, 2)} |"
              f" {r['interface_phi_deg']:.1f} deg, {r['interface_adhesion'] / 1e3:.2f} kPa |")

if __name__ == "__main__":
    main(sys.argv)
