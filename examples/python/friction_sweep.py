#!/usr/bin/env python3
"""A parameter sweep in a loop with a plot at the end: the peak friction angle of a dense
disc sample against the contact friction, from geodem's own biaxial test kind run from
Python (geodem.run returns summary.json as a dict; each run writes its usual folder).

For each contact friction coefficient and seed, the biaxial example (examples/biaxial2d) at
500 discs and one confining stress (100 kPa) to 6 % axial strain. Prints a table of the peak
friction angle (mean and standard deviation over the seeds), writes sweep.json and plots
friction_sweep.png. usage: friction_sweep.py [OUT_DIR] [SEEDS]   (about 2 minutes, 3 seeds)
"""
import json
import statistics
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import geodem  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
OUT = Path(sys.argv[1] if len(sys.argv) > 1 else "runs/friction_sweep")
SEEDS = range(1, 1 + (int(sys.argv[2]) if len(sys.argv) > 2 else 3))
FRICTIONS = [0.1, 0.2, 0.35, 0.5, 0.7]

table = {}
for mu in FRICTIONS:
    for seed in SEEDS:
        summary = geodem.run(
            str(ROOT / "examples" / "biaxial2d" / "scenario.toml"),
            out=str(OUT / f"mu{mu}_seed{seed}"), overwrite=True, threads=2,
            overrides=[f"seed={seed}", "sample.count=500", f"material.friction={mu}",
                       "shear.confining_stress=[1e5]", "shear.max_axial_strain=0.06",
                       "output.plots=false", "output.vtk=false"])
        phi = summary["results"]["tests"][0]["phi_peak_deg"]
        table.setdefault(mu, []).append(phi)
        print(f"friction {mu}, seed {seed}: peak friction angle {phi:.2f} deg", flush=True)

print("| contact friction | peak friction angle (deg), mean | standard deviation | seeds |")
print("| ---: | ---: | ---: | ---: |")
for mu, phis in table.items():
    sd = statistics.stdev(phis) if len(phis) > 1 else float("nan")
    print(f"| {mu} | {statistics.mean(phis):.2f} | {sd:.2f} | {len(phis)} |")
OUT.mkdir(parents=True, exist_ok=True)
(OUT / "sweep.json").write_text(json.dumps({str(k): v for k, v in table.items()}, indent=1))
fig, ax = plt.subplots(figsize=(5.5, 4.0))
means = [statistics.mean(v) for v in table.values()]
sds = [statistics.stdev(v) if len(v) > 1 else 0.0 for v in table.values()]
ax.errorbar(FRICTIONS, means, yerr=sds, marker="o", capsize=3)
ax.set_xlabel("contact friction coefficient")
ax.set_ylabel("peak friction angle (deg)")
ax.set_title(f"Dense discs, biaxial at 100 kPa ({len(SEEDS)} seeds)")
fig.tight_layout()
fig.savefig(OUT / "friction_sweep.png", dpi=110)
