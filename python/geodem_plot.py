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


def plot_triaxial(out, summary, h):
    """q and volumetric strain against axial strain, one curve per confining stress;
    the Mohr circles at the peaks and the fitted envelope with two tests or more."""
    results = summary.get("results", {})
    tests = results.get("tests", [])
    ids = sorted(set(int(t) for t in h["test"]))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 7.0), sharex=True)
    for t in ids:
        rows = [i for i, v in enumerate(h["test"]) if int(v) == t]
        ea = [100 * h["axial_strain"][i] for i in rows]
        label = f"sigma3 = {tests[t]['confining_stress'] / 1e3:g} kPa" if t < len(tests) else f"test {t}"
        ax1.plot(ea, [h["q"][i] / 1e3 for i in rows], label=label)
        ax2.plot(ea, [100 * h["volumetric_strain"][i] for i in rows], label=label)
        if t < len(tests):
            ax1.plot(100 * tests[t]["axial_strain_at_peak"], tests[t]["peak_q"] / 1e3, "k.", ms=8)
    ax1.set_ylabel("q = sigma1 - sigma3 (kPa)")
    ax1.legend(fontsize=8)
    ax1.grid(alpha=0.3)
    ax2.set_xlabel("axial strain (%)")
    ax2.set_ylabel("volumetric strain (%, + contraction)")
    ax2.invert_yaxis()
    ax2.grid(alpha=0.3)
    dim = summary.get("scenario", {}).get("dimension", 3)
    fig.suptitle(("Triaxial" if dim == 3 else "Biaxial") + " compression")
    fig.tight_layout()
    fig.savefig(out / "stress_strain.png", dpi=120)
    plt.close(fig)
    made = ["stress_strain.png"]
    mc = results.get("mohr_coulomb")
    if mc and tests:
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        smax = 0.0
        for t in tests:
            s3 = t["confining_stress"]
            s1 = s3 + t["peak_q"]
            c, r = 0.5 * (s1 + s3), 0.5 * (s1 - s3)
            xs = [c + r * math.cos(math.pi * k / 90) for k in range(91)]
            ys = [r * math.sin(math.pi * k / 90) for k in range(91)]
            ax.plot([x / 1e3 for x in xs], [y / 1e3 for y in ys])
            smax = max(smax, s1)
        tanp = math.tan(math.radians(mc["phi_deg"]))
        ax.plot([0, smax / 1e3], [mc["cohesion"] / 1e3, (mc["cohesion"] + tanp * smax) / 1e3], "k--",
                label=f"c = {mc['cohesion'] / 1e3:.2f} kPa, phi = {mc['phi_deg']:.1f} deg")
        ax.set_xlabel("normal stress (kPa)")
        ax.set_ylabel("shear stress (kPa)")
        ax.set_aspect("equal")
        ax.set_xlim(left=0)
        ax.set_ylim(bottom=0)
        ax.legend(fontsize=8)
        ax.set_title("Mohr circles at the peaks")
        fig.tight_layout()
        fig.savefig(out / "mohr_coulomb.png", dpi=120)
        plt.close(fig)
        made.append("mohr_coulomb.png")
    return made


PLOTTERS = {"scene": plot_scene, "triaxial": plot_triaxial}


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
