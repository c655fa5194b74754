#!/usr/bin/env python3
"""Make the PNG plots of a finished geodem run: geodem_plot.py OUTPUT_DIR.

Reads summary.json (for the kind of run) and history.csv, writes PNG files named
after what they show into the same folder. Uses numpy and matplotlib only.
"""
import csv
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_history(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    header, data = rows[0], rows[1:]
    cols = {name: [] for name in header}
    for row in data:
        if len(row) != len(header):
            continue  # a row cut by a crash is ignored
        for name, value in zip(header, row):
            cols[name].append(float(value))
    return cols


def positive(values):
    return [v if (v > 0 and math.isfinite(v)) else float("nan") for v in values]


def plot_scene(out, summary, h):
    made = []
    t = h["time"]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.semilogy(t, positive(h["kinetic_energy"]), label="kinetic energy (J)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("kinetic energy (J)")
    ax2 = ax.twinx()
    ax2.semilogy(t, positive(h["unbalanced"]), color="tab:red", label="unbalanced force ratio")
    ax2.set_ylabel("unbalanced force ratio", color="tab:red")
    ax.set_title("Energy and equilibrium")
    fig.tight_layout()
    fig.savefig(out / "energy.png", dpi=120)
    plt.close(fig)
    made.append("energy.png")

    walls = summary.get("scenario", {}).get("walls", [])
    dim = summary.get("scenario", {}).get("dimension", 3)
    axes = "xyz"[:dim]
    if walls:
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        for w in walls:
            name = w["name"]
            comps = [h.get(f"wall_{name}_f{a}") for a in axes]
            if any(c is None for c in comps):
                continue
            normal = w.get("normal")
            if normal:
                norm = math.sqrt(sum(x * x for x in normal))
                fn = [-sum(c[i] * n / norm for c, n in zip(comps, normal)) for i in range(len(t))]
            else:
                fn = [math.sqrt(sum(c[i] ** 2 for c in comps)) for i in range(len(t))]
            ax.plot(t, fn, label=name)
        weight = summary.get("results", {}).get("total_weight")
        if weight:
            ax.axhline(weight, color="k", ls="--", lw=0.8, label="total weight")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("normal force on wall (N)" if dim == 3 else "normal force on wall (N/m)")
        ax.legend(fontsize=8)
        ax.set_title("Wall forces")
        fig.tight_layout()
        fig.savefig(out / "wall_forces.png", dpi=120)
        plt.close(fig)
        made.append("wall_forces.png")
    return made


PLOTTERS = {"scene": plot_scene}


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(argv[1])
    summary = json.loads((out / "summary.json").read_text())
    history = read_history(out / "history.csv")
    if not history or not history.get("time"):
        print(f"{out}/history.csv has no rows: nothing to plot", file=sys.stderr)
        return 1
    plotter = PLOTTERS.get(summary.get("kind"))
    if plotter is None:
        print(f"no plots defined for kind {summary.get('kind')!r}", file=sys.stderr)
        return 1
    made = plotter(out, summary, history)
    print("plots: " + ", ".join(str(out / m) for m in made))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
