"""Plots of a pull-out over several seeds and grain sizes, used by geodem_plot.py.

pullout_seeds.png: every seed's tension against the pull, their mean, and the design
estimates (one panel per grain size); pullout_refinement.png: the mean capacity against
d50 / cover, with its spread over the seeds and the fit extrapolated to fine grains;
pullout_sheet_parts.png: the tension each part of the sheet takes off, averaged over the
seeds (geodem_plot_sheet_parts.py).
"""
import csv
import json

import matplotlib.pyplot as plt
import numpy as np
from geodem_plot_sheet_parts import plot_sheet_parts


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], [r for r in rows[1:] if len(r) == len(rows[0])]
    return {name: np.array([float(r[k]) for r in data]) for k, name in enumerate(header)}


def plot_pullout_series(out, summary, save):
    made = []
    groups = summary["results"]["groups"]
    fig, axes = plt.subplots(len(groups), 1, figsize=(6.8, 3.6 * len(groups)), squeeze=False)
    for ax, g in zip(axes[:, 0], groups):
        curves = []
        for run_id in g["runs"]:
            path = out / "runs" / run_id / "history.csv"
            if not path.is_file():
                continue
            h = read_columns(path)
            if h["displacement"].size == 0:
                continue
            curves.append((h["displacement"], h["tension"]))
            ax.plot(h["displacement"] * 1e3, h["tension"] / 1e3, lw=0.8, alpha=0.6)
        if curves:
            top = min(c[0][-1] for c in curves)
            grid = np.linspace(0.0, top, 200)
            mean = np.mean([np.interp(grid, d, t) for d, t in curves], axis=0)
            ax.plot(grid * 1e3, mean / 1e3, "k", lw=2.2, label=f"mean of {len(curves)} seeds")
        for key, style, name in (("T_analytic_slip", "--", "slippage estimate"),
                                 ("T_analytic_soil", ":", "soil-mass estimate")):
            st = g.get(key)
            if st:
                ax.axhline(st["mean"] / 1e3, color="tab:red", ls=style, lw=1.2, label=name)
        t = g.get("T_max")
        title = f"grain radius {g['radius'] * 1e3:.3g} mm"
        if t:
            title += (f": T_max {t['mean'] / 1e3:.3g} kN/m +- {t['std'] / 1e3:.2g} "
                      f"(cv {100 * t['cv']:.0f} %)")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("pull-out displacement (mm)")
        ax.set_ylabel("tension (kN/m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    save(fig, out, "pullout_seeds.png", made)

    # The parts of the sheet, averaged over the first grain size's seeds.
    first = [out / "runs" / r / "history.csv" for r in groups[0]["runs"]]
    runs = [out / "runs" / r / "summary.json" for r in groups[0]["runs"]]
    estimate = None
    if runs and runs[0].is_file():
        estimate = json.loads(runs[0].read_text())["results"].get("sheet_parts", {}).get(
            "slip_estimate")
    plot_sheet_parts(plt, out, save, [read_columns(p) for p in first if p.is_file()], estimate,
                     made, "pullout_sheet_parts.png")

    ref = summary["results"].get("refinement")
    if ref and len(groups) > 1:
        x = np.array([g["d50_over_cover"] for g in groups if g.get("T_max")])
        m = np.array([g["T_max"]["mean"] for g in groups if g.get("T_max")]) / 1e3
        sd = np.array([g["T_max"]["std"] for g in groups if g.get("T_max")]) / 1e3
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        ax.errorbar(x, m, yerr=sd, fmt="o", capsize=4, label="mean over seeds (1 std)")
        xs = np.linspace(0.0, 1.1 * x.max(), 20)
        ax.plot(xs, ref["T_max_fine_limit"] / 1e3 + ref["slope"] / 1e3 * xs, "--",
                label=f"fit: {ref['T_max_fine_limit'] / 1e3:.3g} kN/m at fine grains")
        slip = groups[0].get("T_analytic_slip")
        if slip:
            ax.axhline(slip["mean"] / 1e3, color="tab:red", ls="--", lw=1,
                       label="slippage estimate")
        ax.set_xlim(left=0.0)
        ax.set_xlabel("d50 / cover")
        ax.set_ylabel("T_max (kN/m)")
        ax.set_title("Capacity against grain size")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        save(fig, out, "pullout_refinement.png", made)
    return made
