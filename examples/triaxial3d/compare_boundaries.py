#!/usr/bin/env python3
"""The flagship triaxial test between walls (scenario.toml) and in a periodic cell
(periodic.toml), seeds 1 to N, two runs at a time: prints the table of the README (mean and
standard deviation over the seeds) and draws every seed's q and volumetric strain against the
axial strain for both boundaries.

    examples/triaxial3d/compare_boundaries.py OUT [--seeds 3] [--geodem build/geodem]

Writes OUT/boundaries.md, OUT/boundaries.json and OUT/boundaries.png (copied to expected/ by
scripts/refresh-examples.sh --all).
"""
import argparse
import csv
import json
import statistics
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
REUSE = False  # --reuse: runs already in OUT are read, not run again
CASES = {"walls": HERE / "scenario.toml", "periodic": HERE / "periodic.toml"}


def run(geodem, scenario, out, seed, reuse=None, sets=()):
    """Runs `scenario` with `seed` (and `--set` each of `sets`) into `out` on one thread, unless
    `reuse` (by default --reuse) and it ran already; returns its summary and history rows."""
    if not (REUSE if reuse is None else reuse) or not (out / "summary.json").exists():
        cmd = [geodem, "run", str(scenario), "--out", str(out), "--overwrite", "--quiet",
               "--threads", "1", "--set", f"seed={seed}"]
        for s in sets:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True)
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "history.csv") as f:
        rows = list(csv.DictReader(f))
    return summary, rows


def mean_std(values):
    return statistics.mean(values), statistics.stdev(values) if len(values) > 1 else 0.0


def seed_arguments():
    """The arguments of the seed scripts of this folder: OUT, --seeds, --geodem, --reuse."""
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--geodem", default="build/geodem")
    ap.add_argument("--reuse", action="store_true", help="read the runs already in OUT")
    return ap


def main():
    a = seed_arguments().parse_args()
    global REUSE
    REUSE = a.reuse
    out = Path(a.out)
    jobs = [(name, seed) for name in CASES for seed in range(1, a.seeds + 1)]
    with ThreadPoolExecutor(2) as pool:
        done = list(pool.map(lambda j: run(a.geodem, CASES[j[0]], out / f"{j[0]}_seed{j[1]}", j[1]),
                             jobs))
    runs = {name: [] for name in CASES}
    for (name, _), result in zip(jobs, done):
        runs[name].append(result)

    quantities = [
        ("porosity after radius growth", lambda s: s["results"]["preparation"]["porosity_after_compaction"], "{:.3f}"),
        ("porosity at the start of compression", lambda s: s["results"]["porosity_initial"], "{:.3f}"),
        ("peak deviator q (kPa)", lambda s: s["results"]["peak_q"] / 1e3, "{:.0f}"),
        ("axial strain at the peak (%)", lambda s: 100 * s["results"]["axial_strain_at_peak"], "{:.1f}"),
        ("peak friction angle (deg)", lambda s: s["results"]["phi_peak_deg"], "{:.1f}"),
        ("residual friction angle (deg)", lambda s: s["results"]["phi_residual_deg"], "{:.1f}"),
        ("Young's modulus E50 (MPa)", lambda s: s["results"]["young_modulus"] / 1e6, "{:.1f}"),
        ("Poisson's ratio", lambda s: s["results"]["poisson_ratio"], "{:.2f}"),
        ("dilatancy angle (deg)", lambda s: s["results"]["dilatancy_deg"], "{:.1f}"),
        ("wall time per run (s)", lambda s: s["timing"]["wall_s"], "{:.0f}"),
    ]
    table = {}
    lines = [f"| quantity ({a.seeds} seeds, mean +- std) | walls | periodic cell |",
             "| --- | ---: | ---: |"]
    for label, get, fmt in quantities:
        cells = []
        for name in CASES:
            m, s = mean_std([get(summary) for summary, _ in runs[name]])
            table.setdefault(label, {})[name] = {"mean": m, "std": s}
            cells.append(f"{fmt.format(m)} +- {fmt.format(s)}")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    (out / "boundaries.md").write_text("\n".join(lines) + "\n")
    (out / "boundaries.json").write_text(json.dumps(table, indent=1))
    print("\n".join(lines))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax_q, ax_v) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    colours = {"walls": "tab:blue", "periodic": "tab:red"}
    for name in CASES:
        for k, (_, rows) in enumerate(runs[name]):
            eps = [100 * float(r["axial_strain"]) for r in rows]
            ax_q.plot(eps, [float(r["q"]) / 1e3 for r in rows], color=colours[name], lw=1,
                      label=name if k == 0 else None)
            ax_v.plot(eps, [100 * float(r["volumetric_strain"]) for r in rows],
                      color=colours[name], lw=1)
    ax_q.set_ylabel("q (kPa)")
    ax_q.legend(title=f"seeds 1-{a.seeds}")
    ax_v.set_ylabel("volumetric strain (%, contraction +)")
    ax_v.set_xlabel("axial strain (%)")
    ax_q.set_title("2000 spheres at 100 kPa, porosity 0.41: walls and periodic cell")
    fig.tight_layout()
    fig.savefig(out / "boundaries.png", dpi=110)


if __name__ == "__main__":
    main()
