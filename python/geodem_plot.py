#!/usr/bin/env python3
"""Make the PNG plots of a finished geodem run: geodem_plot.py OUTPUT_DIR.

geodem_plot.py --wait OUTPUT_DIR: what a run starts as it begins. It loads its libraries while
the run computes, then reads a line from its standard input: "go" draws the plots of the
finished run, anything else (the end of the input when the run failed) leaves without drawing.

Reads summary.json (for the kind of run) and history.csv (the studies, kinds series,
rate_study and calibrate, have none: their summary and CSV tables instead), writes
PNG files named after what they show into the same folder. Uses numpy and
matplotlib only.
"""
import csv
import json
import math
import os
import signal
import sys
from pathlib import Path

if __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--wait":
    # Ctrl-C reaches the run's whole process group: the run ends on its own terms and closes
    # our input, which ends this process without a traceback.
    signal.signal(signal.SIGINT, signal.SIG_IGN)

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402


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


def save(fig, out, name, made):
    """Writes one figure as out/name (PNG, 120 dpi), closes it and notes its name."""
    fig.tight_layout()
    fig.savefig(out / name, dpi=120)
    plt.close(fig)
    made.append(name)


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
    stages = summary.get("results", {}).get("stages", [])

    def mark_stages(axis):
        """Dotted lines at the stages' starts, named at the top."""
        for st in stages[1:]:
            axis.axvline(st["start_time"], color="0.5", ls=":", lw=0.8)
        for st in stages:
            axis.text(st["start_time"], 0.98, st["name"] + " ", transform=axis.get_xaxis_transform(),
                      fontsize=7, va="top", ha="right", rotation=90, color="0.3")

    mark_stages(ax)
    save(fig, out, "energy.png", made)

    scenario = summary.get("scenario", {})
    # The walls of the scene, then those its stages add.
    walls = list(scenario.get("walls", []))
    for st in scenario.get("stages", []):
        walls += st.get("add_walls", [])
    dim = summary.get("scenario", {}).get("dimension", 3)
    axes = "xyz"[:dim]
    if walls:
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        for w in walls:
            name = w["name"]
            # A plane or segment wall has its own columns; a polyline's segments are walls
            # NAME_0, NAME_1, ... with a column group each.
            parts = [name] if f"wall_{name}_f{axes[0]}" in h else []
            k = 0
            while f"wall_{name}_{k}_f{axes[0]}" in h:
                parts.append(f"{name}_{k}")
                k += 1
            for part in parts:
                comps = [h.get(f"wall_{part}_f{a}") for a in axes]
                if any(c is None for c in comps):
                    continue
                normal = w.get("normal") if part == name else None
                if normal:
                    norm = math.sqrt(sum(x * x for x in normal))
                    fn = [-sum(c[i] * n / norm for c, n in zip(comps, normal))
                          for i in range(len(t))]
                else:  # the force's magnitude (a segment's normal has no set sign)
                    fn = [math.sqrt(sum(c[i] ** 2 for c in comps)) for i in range(len(t))]
                ax.plot(t, fn, label=part)
        weight = summary.get("results", {}).get("total_weight")
        if weight:
            ax.axhline(weight, color="k", ls="--", lw=0.8, label="total weight")
        ax.set_xlabel("time (s)")
        unit = "N" if dim == 3 else "N/m"
        ax.set_ylabel(f"force on wall ({unit}): normal; polyline segments: magnitude")
        ax.legend(fontsize=8)
        mark_stages(ax)
        ax.set_title("Wall forces")
        save(fig, out, "wall_forces.png", made)
    return made


def plot_triaxial(out, summary, h):
    """q and volumetric strain (undrained: the excess pore pressure) against axial strain,
    one curve per confining stress; the stress path p'-q; the Mohr circles at the peaks and
    the fitted envelope with two tests or more."""
    results = summary.get("results", {})
    tests = results.get("tests", [])
    ids = sorted(set(int(t) for t in h["test"]))
    undrained = "excess_pore_pressure" in h
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 7.0), sharex=True)
    fig_p, ax_p = plt.subplots(figsize=(6.4, 4.6))
    for t in ids:
        rows = [i for i, v in enumerate(h["test"]) if int(v) == t]
        ea = [100 * h["axial_strain"][i] for i in rows]
        label = f"sigma3 = {tests[t]['confining_stress'] / 1e3:g} kPa" if t < len(tests) else f"test {t}"
        ax1.plot(ea, [h["q"][i] / 1e3 for i in rows], label=label)
        if undrained:
            ax2.plot(ea, [h["excess_pore_pressure"][i] / 1e3 for i in rows], label=label)
        else:
            ax2.plot(ea, [100 * h["volumetric_strain"][i] for i in rows], label=label)
        ax_p.plot([h["p"][i] / 1e3 for i in rows], [h["q"][i] / 1e3 for i in rows], label=label)
        if t < len(tests):
            ax1.plot(100 * tests[t]["axial_strain_at_peak"], tests[t]["peak_q"] / 1e3, "k.", ms=8)
    ax1.set_ylabel("q = sigma1 - sigma3 (kPa)")
    ax1.legend(fontsize=8)
    ax1.grid(alpha=0.3)
    ax2.set_xlabel("axial strain (%)")
    if undrained:
        ax2.set_ylabel("excess pore pressure (kPa)")
    else:
        ax2.set_ylabel("volumetric strain (%, + contraction)")
        ax2.invert_yaxis()
    ax2.grid(alpha=0.3)
    dim = summary.get("scenario", {}).get("dimension", 3)
    fig.suptitle(("Triaxial" if dim == 3 else "Biaxial") + (" compression, undrained (constant volume)"
                                                           if undrained else " compression"))
    made = []
    save(fig, out, "stress_strain.png", made)
    ax_p.set_xlabel("p' (kPa)")
    ax_p.set_ylabel("q (kPa)")
    ax_p.set_xlim(left=0)
    ax_p.set_ylim(bottom=0)
    ax_p.grid(alpha=0.3)
    ax_p.legend(fontsize=8)
    ax_p.set_title("Effective stress path" + (" (undrained)" if undrained else ""))
    save(fig_p, out, "stress_path.png", made)
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
        save(fig, out, "mohr_coulomb.png", made)
    return made


# Two contrasting colours for the alternating vertical bands of soil (the
# deformed stripes show where the soil moved), grey for grains left out.
BAND_COLOURS = ("#3b6ea5", "#e3c16f")
UNBANDED_COLOUR = "#b5b5b5"
SHEET_COLOUR = "#c0392b"


def read_state(path):
    """Columns of a CSV file as float lists, or None when the file is absent."""
    if not path.is_file():
        return None
    table = read_history(path)
    return table if table and all(table.values()) else None  # header only: nothing to draw


def plot_pullout(out, summary, h):
    """Pull-out curve, tension along the sheet and the soil around the sheet
    before and after pulling. Optional files that are missing are skipped."""
    results = summary.get("results", {})
    made = []
    u = [1e3 * v for v in h.get("displacement", [])]
    tension = [v / 1e3 for v in h.get("tension", [])]
    if u and len(tension) == len(u):
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        ax.plot(u, tension, color="tab:blue", label="tension at the pulled end")
        t_slip = results.get("T_analytic_slip")
        if t_slip is not None and math.isfinite(t_slip):
            ax.axhline(t_slip / 1e3, color="k", ls="--", lw=0.8, label="analytic slippage estimate")
        t_max, u_max = results.get("T_max"), results.get("displacement_at_T_max")
        if t_max is None or u_max is None:
            i = max(range(len(tension)), key=lambda k: tension[k])  # fall back on the history
            t_max, u_max = 1e3 * tension[i], u[i] / 1e3
        ax.plot(1e3 * u_max, t_max / 1e3, "k.", ms=9)
        ax.annotate(f"T_max = {t_max / 1e3:.3g} kN/m\nat u = {1e3 * u_max:.3g} mm",
                    xy=(1e3 * u_max, t_max / 1e3), xytext=(8, 6), textcoords="offset points",
                    fontsize=8, va="bottom", bbox={"fc": "white", "ec": "none", "alpha": 0.8})
        ax.set_xlabel("pulled-end displacement (mm)")
        ax.set_ylabel("tension at the pulled end (kN/m)", color="tab:blue")
        # Headroom for the T_max label above the curve.
        top = max(max(tension), t_max / 1e3, 1e-9)
        if t_slip is not None and math.isfinite(t_slip):
            top = max(top, t_slip / 1e3)  # the estimate stays in view
        ax.set_ylim(min(0.0, min(tension)), 1.2 * top)
        ax.grid(alpha=0.3)
        handles, labels = ax.get_legend_handles_labels()
        soil = h.get("soil_displacement")
        if soil and len(soil) == len(u):
            ax2 = ax.twinx()
            ax2.plot(u, [1e3 * v for v in soil], color="tab:green", lw=1.0,
                     label="mean soil displacement (anchoring zone)")
            ax2.set_ylabel("mean soil displacement (mm)", color="tab:green")
            ax2.set_ylim(bottom=min(0.0, 1e3 * min(soil)))  # zero level with the tension axis
            h2, l2 = ax2.get_legend_handles_labels()
            handles, labels = handles + h2, labels + l2
        ax.legend(handles, labels, fontsize=8, loc="lower right")
        ax.set_title("Pull-out test")
        save(fig, out, "pullout.png", made)

    if "runout_carried" in h and u:
        from geodem_plot_sheet_parts import plot_sheet_parts
        plot_sheet_parts(plt, out, save, [{k: np.array(v) for k, v in h.items()}],
                         results.get("sheet_parts", {}).get("slip_estimate"), made)

    profiles = read_state(out / "tension_profiles.csv")
    if profiles and profiles.get("s"):
        # Rows are grouped by pulled-end displacement; keep the order of the file.
        groups = {}
        for d, s, t in zip(profiles["displacement"], profiles["s"], profiles["tension"]):
            groups.setdefault(d, ([], []))
            groups[d][0].append(s)
            groups[d][1].append(t / 1e3)
        cmap = plt.get_cmap("viridis")
        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        for k, (d, (s, t)) in enumerate(groups.items()):
            colour = cmap(k / max(1, len(groups) - 1) * 0.9)
            ax.plot(s, t, color=colour, marker=".", ms=3, label=f"u = {round(1e3 * d, 2):g} mm")
        ax.set_xlabel("distance along the sheet from the pulled end, s (m)")
        ax.set_ylabel("tension (kN/m)")
        ax.set_xlim(left=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title("Tension along the sheet")
        save(fig, out, "tension_profiles.png", made)

    states = {}
    for name in ("initial", "final"):
        grains = read_state(out / "states" / f"grains_{name}.csv")
        sheet = read_state(out / "states" / f"sheet_{name}.csv")
        if grains or sheet:
            states[name] = (grains, sheet)
    if states:
        # One set of limits for both pictures, so that they compare.
        xs, ys = [], []
        for grains, sheet in states.values():
            if grains:
                for x, y, r in zip(grains["x"], grains["y"], grains["radius"]):
                    xs += [x - r, x + r]
                    ys += [y - r, y + r]
            if sheet:
                xs += sheet["x"]
                ys += sheet["y"]
        pad = 0.02 * max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)
        xlim = (min(xs) - pad, max(xs) + pad)
        ylim = (min(ys) - pad, max(ys) + pad)
        aspect = (ylim[1] - ylim[0]) / (xlim[1] - xlim[0])
        size = (6.4, min(9.0, max(3.0, 5.6 * aspect + 1.0)))
        u_final = u[-1] if u else None
        for name, (grains, sheet) in states.items():
            fig, ax = plt.subplots(figsize=size)
            if grains:
                n = len(grains["x"])
                columns = grains.get("column", [-1.0] * n)
                colours = [UNBANDED_COLOUR if c < 0 else BAND_COLOURS[int(c) % len(BAND_COLOURS)]
                           for c in columns]
                d = [2 * r for r in grains["radius"]]
                # Edges only while the grains are big enough on the picture to show them.
                edge = 0.2 if n <= 3000 else 0.0
                ax.add_collection(EllipseCollection(
                    d, d, [0.0] * n, units="xy", offsets=list(zip(grains["x"], grains["y"])),
                    offset_transform=ax.transData, facecolors=colours, edgecolors="0.25",
                    linewidths=edge))
            if sheet:
                order = sorted(range(len(sheet["x"])), key=lambda k: sheet["node"][k]) \
                    if "node" in sheet else range(len(sheet["x"]))
                ax.plot([sheet["x"][k] for k in order], [sheet["y"][k] for k in order],
                        color=SHEET_COLOUR, lw=2.5, solid_capstyle="round", zorder=3)
            ax.set_xlim(*xlim)
            ax.set_ylim(*ylim)
            ax.set_aspect("equal")
            ax.set_xlabel("x (m)")
            ax.set_ylabel("y (m)")
            if name == "initial":
                title = "Pull-out: initial state (u = 0 mm)"
            elif u_final is not None:
                title = f"Pull-out: final state (u = {u_final:.3g} mm)"
            else:
                title = "Pull-out: final state"
            ax.set_title(title)
            save(fig, out, f"pullout_{name}.png", made)
    return made


# --- Studies (no history.csv: the results and tables of the runs) -------------------
# Drawn by geodem_plot_studies.py and geodem_plot_calibrate.py, loaded when needed.


def plot_series(out, summary, h=None):
    from geodem_plot_studies import plot_series as plot
    return plot(out, summary, save)


def plot_rate_study(out, summary, h=None):
    from geodem_plot_studies import plot_rate_study as plot
    return plot(out, summary, save)


def plot_calibrate(out, summary, h=None):
    from geodem_plot_calibrate import plot_calibrate as plot
    return plot(out, summary, save)


STUDY_KINDS = {"series", "rate_study", "calibrate"}


def plot_interface(out, summary, h):
    from geodem_plot_interface import plot_interface_shear
    return plot_interface_shear(out, summary, h, save)


def plot_element(out, summary, h):
    import geodem_plot_element as element
    plot = {"isotropic": element.plot_stress_steps, "oedometer": element.plot_stress_steps,
            "simple_shear": element.plot_simple_shear,
            "direct_shear": element.plot_simple_shear,
            "cyclic_triaxial": element.plot_cyclic}[summary["kind"]]
    return plot(out, summary, h, save)


PLOTTERS = {"scene": plot_scene, "triaxial": plot_triaxial, "pullout": plot_pullout,
            "interface_shear": plot_interface,
            "isotropic": plot_element, "oedometer": plot_element, "simple_shear": plot_element,
            "cyclic_triaxial": plot_element, "direct_shear": plot_element,
            "series": plot_series, "rate_study": plot_rate_study, "calibrate": plot_calibrate}


def main(argv):
    if len(argv) == 3 and argv[1] == "--wait":
        if sys.stdin.readline().strip() != "go":
            return 0
        argv = [argv[0], argv[2]]
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(argv[1])
    summary = json.loads((out / "summary.json").read_text())
    kind = summary.get("kind")
    plotter = PLOTTERS.get(kind)
    if plotter is None:
        print(f"no plots defined for kind {kind!r}", file=sys.stderr)
        return 1
    if kind == "pullout" and "groups" in summary.get("results", {}):
        from geodem_plot_pullout_series import plot_pullout_series
        made = plot_pullout_series(out, summary, save)
        print("plots: " + ", ".join(str(out / m) for m in made))
        return 0
    # The studies write no history.csv: their plots use the summary and their tables.
    history = read_history(out / "history.csv") if (out / "history.csv").is_file() else {}
    if kind not in STUDY_KINDS and (not history or not history.get("time")):
        print(f"{out}/history.csv has no rows: nothing to plot", file=sys.stderr)
        return 1
    made = plotter(out, summary, history)
    print("plots: " + ", ".join(str(out / m) for m in made))
    return 0


if __name__ == "__main__":
    code = main(sys.argv)
    if len(sys.argv) > 1 and sys.argv[1] == "--wait":
        # The run waits for us: leave without the interpreter's teardown of numpy and
        # matplotlib (0.06 s of the 0.29 s between "go" and our exit on B1's two figures).
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)
