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

# Studied quantities: a plain name, the factor to the plotted unit and that unit.
QUANTITIES = {
    "peak_q": ("peak deviator stress q", 1e-3, "kPa"),
    "sigma1_peak": ("peak major principal stress sigma1", 1e-3, "kPa"),
    "phi_peak_deg": ("peak friction angle", 1.0, "deg"),
    "phi_residual_deg": ("residual friction angle", 1.0, "deg"),
    "young_modulus": ("Young's modulus", 1e-6, "MPa"),
    "poisson_ratio": ("Poisson's ratio", 1.0, "-"),
    "dilatancy_deg": ("dilatancy angle", 1.0, "deg"),
    "axial_strain_at_peak": ("axial strain at the peak", 100.0, "%"),
    "cohesion": ("cohesion", 1e-3, "kPa"),
}


def quantity_info(name):
    """(plain name, factor to the plotted unit, unit, 'name (unit)' axis label)."""
    label, factor, unit = QUANTITIES.get(
        name, (name.replace("_", " "), 1.0, "deg" if name.endswith("_deg") else ""))
    return label, factor, unit, f"{label} ({unit})" if unit else label


def finite(x):
    """True for a number that is neither None, NaN nor infinite."""
    try:
        return x is not None and math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


def number(x, default=float("nan")):
    return float(x) if finite(x) else default


def read_table(path):
    """Columns of a CSV file as numpy arrays (cells that are no numbers become NaN),
    or None when the file is absent or has no rows."""
    if not path.is_file():
        return None
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        return None
    header = rows[0]
    cols = {name: [] for name in header}
    for row in rows[1:]:
        if len(row) != len(header):
            continue
        for name, cell in zip(header, row):
            try:
                cols[name].append(float(cell))
            except ValueError:
                cols[name].append(float("nan"))
    return {name: np.array(v, dtype=float) for name, v in cols.items()}


def fit_text(fit, factor, unit, variable):
    """'a unit + b unit variable, r2 = ...' for a {intercept, slope, r2} fit."""
    a, b = number(fit.get("intercept")), number(fit.get("slope"))
    r2 = number(fit.get("r2"))
    u = f" {unit}" if unit not in ("", "-") else ""
    text = f"{a * factor:.4g}{u} + {b * factor:.4g}{u} {variable}"
    if finite(r2):
        text += f", r2 = {r2:.3f}"
    return text


def plot_series(out, summary, h=None):
    """Representativeness of the sample size: the value against d0/L with the fit
    extrapolated to an infinite sample, the bias against the grain count, and the
    standard deviation against d0/L."""
    results = summary.get("results", {})
    made = []
    name = results.get("quantity", "value")
    label, factor, unit, ylabel = quantity_info(name)
    dim = int(summary.get("scenario", {}).get("dimension", 3) or 3)
    groups = [g for g in results.get("groups", [])
              if finite(g.get("count")) and finite(g.get("d0_over_L"))]
    groups.sort(key=lambda g: g["count"])
    mean_fit = results.get("mean_fit", {}) or {}
    std_fit = results.get("std_fit", {}) or {}
    extrapolated = number(results.get("extrapolated"), number(mean_fit.get("intercept")))
    tol = number(results.get("tolerance"))
    ref = abs(extrapolated) if finite(extrapolated) else float("nan")
    runs = read_table(out / "runs.csv")
    if not groups and runs is None:
        return made

    # Sample shape d0/L = C count^(-1/D): from the summary, else from the groups.
    size_c = number(results.get("size_constant"))
    if not (size_c > 0) and groups:
        size_c = float(np.mean([g["d0_over_L"] * g["count"] ** (1.0 / dim) for g in groups]))

    fig, (ax, axb) = plt.subplots(1, 2, figsize=(12.0, 4.8))
    if runs is not None and "d0_over_L" in runs and "value" in runs:
        x, y = runs["d0_over_L"], runs["value"]
        ok = np.isfinite(x) & np.isfinite(y)
        ax.plot(x[ok], factor * y[ok], ".", color="0.6", ms=4, label="single runs", zorder=2)
    xg = np.array([g["d0_over_L"] for g in groups])
    mg = np.array([number(g.get("mean")) for g in groups])
    sg = np.array([number(g.get("std"), 0.0) for g in groups])
    ok = np.isfinite(mg)
    if ok.any():
        ax.errorbar(xg[ok], factor * mg[ok], yerr=factor * sg[ok], fmt="o", color="tab:blue",
                    ms=6, capsize=4, label="mean of each grain count, +-1 std", zorder=4)
        for j, (g, x0, m0) in enumerate(zip(groups, xg, mg)):
            if finite(m0):
                runs_text = f", {int(g['runs'])} run" + ("s" if g.get("runs") != 1 else "") \
                    if finite(g.get("runs")) else ""
                # Labels alternately above and below, so that neighbours do not overlap.
                ax.annotate(f"{int(g['count'])} grains{runs_text}", xy=(x0, factor * m0),
                            xytext=(6, 6 if j % 2 == 0 else -12), textcoords="offset points",
                            fontsize=7, color="tab:blue")
    xmax = 1.08 * max([v for v in xg if finite(v)] +
                      ([float(np.nanmax(runs["d0_over_L"]))] if runs is not None and
                       "d0_over_L" in runs and np.isfinite(runs["d0_over_L"]).any() else []) +
                      [1e-12])
    a, b = number(mean_fit.get("intercept")), number(mean_fit.get("slope"))
    if finite(a) and finite(b):
        xs = np.linspace(0.0, xmax, 50)
        ax.plot(xs, factor * (a + b * xs), "k--", lw=1.0,
                label="linear fit: " + fit_text(mean_fit, factor, unit, "d0/L"))
        sa, sb = number(std_fit.get("intercept")), number(std_fit.get("slope"))
        if finite(sa) and finite(sb):
            spread = np.maximum(0.0, sa + sb * xs)
            ax.fill_between(xs, factor * (a + b * xs - spread), factor * (a + b * xs + spread),
                            color="0.5", alpha=0.12, lw=0, label="fit +-1 fitted std")
    if finite(extrapolated):
        err = number(mean_fit.get("intercept_error"), 0.0)
        ax.errorbar([0.0], [factor * extrapolated], yerr=[factor * err] if err > 0 else None,
                    fmt="*", color="tab:red", ms=13, capsize=4, zorder=5,
                    label=f"extrapolated to d0/L -> 0: {factor * extrapolated:.4g} {unit}")
        if finite(tol) and ref > 0:
            ax.axhspan(factor * (extrapolated - tol * ref), factor * (extrapolated + tol * ref),
                       color="tab:green", alpha=0.12, lw=0,
                       label=f"extrapolated +-{100 * tol:g} % (tolerance)")
    d_tol = number(results.get("d0_over_L_for_tolerance"))
    if finite(d_tol) and 0 < d_tol < xmax:
        ax.axvline(d_tol, color="tab:green", ls=":", lw=1.0,
                   label=f"d0/L for the tolerance: {d_tol:.3g}")
    ax.set_xlim(-0.02 * xmax, xmax)
    ax.set_xlabel("mean grain diameter / sample height, d0/L (-)")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(f"{label[0].upper() + label[1:]} against sample size")

    # Bias (%) against the grain count: measured means and the fit.
    counts = np.array([float(g["count"]) for g in groups])
    bias = np.array([100 * number(g.get("bias")) for g in groups])
    bias_fit = np.array([100 * number(g.get("bias_fit")) for g in groups])
    with_scatter = results.get("criterion") == "bias_and_scatter"
    n_tol = number(results.get("count_for_tolerance"))
    if len(counts):
        lo = counts.min() / 2
        hi = counts.max() * 2
        if finite(n_tol) and n_tol > 0:
            lo, hi = min(lo, n_tol / 2), max(hi, n_tol * 2)
        hi = min(hi, 1e10)
        ok = np.isfinite(bias)
        axb.plot(counts[ok], bias[ok], "o", color="tab:blue", ms=6, label="measured (group means)",
                 zorder=4)
        if finite(b) and ref > 0 and size_c > 0:
            ns = np.geomspace(max(lo, 1.0), hi, 200)
            d = size_c * ns ** (-1.0 / dim)
            axb.plot(ns, 100 * b * d / ref, "k--", lw=1.0, label="from the fit of the means")
            sa, sb = number(std_fit.get("intercept")), number(std_fit.get("slope"))
            if with_scatter and finite(sa) and finite(sb):
                # The criterion: |bias| + one fitted std, as analysed by geodem.
                crit = 100 * (abs(b) * d + np.maximum(0.0, sa + sb * d)) / ref
                axb.plot(ns, crit, "-", color="tab:purple", lw=1.0,
                         label="|bias| + 1 std, from the fits")
        else:
            ok = np.isfinite(bias_fit)
            axb.plot(counts[ok], bias_fit[ok], "s", mfc="none", color="k", ms=6,
                     label="from the fit of the means")
        if with_scatter:
            scatter = np.array([100 * number(g.get("scatter")) for g in groups])
            crit = np.abs(bias) + scatter
            ok = np.isfinite(crit)
            axb.plot(counts[ok], crit[ok], "D", color="tab:purple", ms=5, mfc="none",
                     label="|bias| + 1 std, measured")
        if finite(tol):
            axb.axhspan(-100 * tol, 100 * tol, color="tab:green", alpha=0.15, lw=0,
                        label=f"tolerance +-{100 * tol:g} %")
        axb.axhline(0.0, color="k", lw=0.6)
        if finite(n_tol) and n_tol > 0:
            axb.axvline(n_tol, color="tab:green", ls=":", lw=1.2,
                        label=f"grains for the tolerance: {n_tol:.4g}")
        elif "count_for_tolerance" in results:  # null: no sample size is close enough
            axb.plot([], [], " ", label="no grain count reaches the tolerance (fit)")
        smallest = number(results.get("smallest_tested_count"), 0.0)
        if smallest > 0:
            axb.axvline(smallest, color="tab:orange", ls="-.", lw=1.0,
                        label=f"smallest tested count within it: {smallest:.0f}")
        axb.set_xscale("log")
        axb.set_xlim(lo, hi)
    axb.set_xlabel("grains in the sample")
    axb.set_ylabel("bias relative to the extrapolated value (%)")
    axb.grid(alpha=0.3, which="both")
    axb.legend(fontsize=7)
    axb.set_title("Bias of the mean against sample size")
    save(fig, out, "representativeness_mean.png", made)

    # Standard deviation of each group against d0/L.
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    sd = np.array([number(g.get("std")) for g in groups])
    single = np.array([number(g.get("runs"), 2.0) < 2 for g in groups], dtype=bool)
    ok = np.isfinite(sd) & ~single
    ax.plot(xg[ok], factor * sd[ok], "o", color="tab:blue", ms=6,
            label="standard deviation of each grain count")
    ok1 = np.isfinite(sd) & single
    if ok1.any():
        ax.plot(xg[ok1], factor * sd[ok1], "o", mfc="none", color="tab:blue", ms=6,
                label="single run (no spread)")
    for g, x0, s0 in zip(groups, xg, sd):
        if finite(s0):
            ax.annotate(f"{int(g['count'])} grains", xy=(x0, factor * s0), xytext=(5, 5),
                        textcoords="offset points", fontsize=7, color="tab:blue")
    sa, sb = number(std_fit.get("intercept")), number(std_fit.get("slope"))
    if finite(sa) and finite(sb):
        xs = np.linspace(0.0, xmax, 50)
        ax.plot(xs, factor * (sa + sb * xs), "k--", lw=1.0,
                label="linear fit: " + fit_text(std_fit, factor, unit, "d0/L"))
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlim(-0.02 * xmax, xmax)
    ax.set_xlabel("mean grain diameter / sample height, d0/L (-)")
    ax.set_ylabel(f"standard deviation of the {label}" + (f" ({unit})" if unit else ""))
    if ref > 0:
        sec = ax.secondary_yaxis("right", functions=(lambda v: 100 * v / (factor * ref),
                                                     lambda p: p * factor * ref / 100))
        sec.set_ylabel("relative to the extrapolated mean (%)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(f"Scatter of the {label} against sample size")
    save(fig, out, "representativeness_std.png", made)
    return made


def damping_colours(values):
    """Distinct colours for up to ten damping values, a colour scale beyond."""
    n = len(values)
    if n <= 10:
        cmap = plt.get_cmap("tab10")
        return {d: cmap(k) for k, d in enumerate(values)}
    cmap = plt.get_cmap("viridis")
    return {d: cmap(0.9 * k / (n - 1)) for k, d in enumerate(values)}


def plot_rate_study(out, summary, h=None):
    """Strain-rate effects: the value against strain rate per damping coefficient,
    and against damping x strain rate with the joint fit value = QS + k D rate."""
    results = summary.get("results", {})
    made = []
    name = results.get("quantity", "value")
    label, factor, unit, ylabel = quantity_info(name)
    runs = results.get("runs")
    if runs:
        rate = np.array([number(r.get("strain_rate")) for r in runs])
        damp = np.array([number(r.get("damping")) for r in runs])
        value = np.array([number(r.get("value")) for r in runs])
        bias = np.array([number(r.get("bias")) for r in runs])
        inertial = np.array([number(r.get("inertial_number")) for r in runs])
    else:
        table = read_table(out / "runs.csv")
        if table is None:
            return made
        nan = np.full(len(next(iter(table.values()))), np.nan)
        rate, damp, value = (table.get(k, nan) for k in ("strain_rate", "damping", "value"))
        bias, inertial = table.get("bias", nan), table.get("inertial_number", nan)
    ok = np.isfinite(rate) & np.isfinite(damp) & np.isfinite(value)
    if not ok.any():
        return made
    qs = number(results.get("quasi_static"))
    fit = results.get("fit", {}) or {}
    k = number(results.get("k"), number(fit.get("slope")))
    tol = number(results.get("tolerance"))
    dampings = sorted(set(damp[ok].tolist()))
    colours = damping_colours(dampings)
    per = {number(p.get("damping")): p for p in results.get("per_damping", []) or []}

    fig, ax = plt.subplots(figsize=(7.2, 4.8))
    rmin, rmax = rate[ok].min(), rate[ok].max()
    log_x = rmin > 0 and rmax / rmin > 10
    xs = np.geomspace(rmin, rmax, 100) if log_x else np.linspace(0.0, 1.05 * rmax, 100)
    if finite(qs):
        ax.axhline(factor * qs, color="k", ls="--", lw=0.8,
                   label=f"quasi-static value (joint fit): {factor * qs:.4g} {unit}")
        if finite(tol):
            ax.axhspan(factor * (qs - tol * abs(qs)), factor * (qs + tol * abs(qs)),
                       color="tab:green", alpha=0.12, lw=0, label=f"+-{100 * tol:g} % (tolerance)")
    for d in dampings:
        sel = ok & (damp == d)
        p = per.get(d, {})
        extra = ""
        if finite(p.get("max_rate")) and finite(tol):
            extra = f", rate for {100 * tol:g} % bias: {p['max_rate']:.3g} /s"
        ax.plot(rate[sel], factor * value[sel], "o", color=colours[d], ms=6,
                label=f"damping {d:g}" + extra)
        a, b = number(p.get("intercept")), number(p.get("slope"))
        if len(set(rate[sel].tolist())) >= 2 and finite(a) and finite(b):
            r2 = number(p.get("r2"))
            ax.plot(xs, factor * (a + b * xs), "-", color=colours[d], lw=1.0,
                    label=f"  fit at damping {d:g}" + (f" (r2 = {r2:.2f})" if finite(r2) else ""))
    if log_x:
        ax.set_xscale("log")
    else:
        ax.set_xlim(left=0)
    ax.set_xlabel("axial strain rate (1/s)")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title(f"Strain-rate effect on the {label}")
    save(fig, out, "rate_effect.png", made)

    # value = QS + k D rate for all runs; rate bias against the inertial number.
    has_inertial = bool((ok & np.isfinite(bias) & np.isfinite(inertial) & (inertial > 0)).any())
    if has_inertial:
        fig, (ax, axb) = plt.subplots(1, 2, figsize=(12.0, 4.8))
    else:
        fig, ax = plt.subplots(figsize=(6.4, 4.8))
    x = damp * rate
    for d in dampings:
        sel = ok & (damp == d)
        ax.plot(x[sel], factor * value[sel], "o", color=colours[d], ms=6, label=f"damping {d:g}")
    xmax = 1.08 * max(float(np.nanmax(x[ok])), 1e-12)
    if finite(qs) and finite(k):
        # The fitted values in the legend: a text box could hide runs or the legend.
        plain = unit if unit not in ("", "-") else ""
        err_a, err_b = number(fit.get("intercept_error")), number(fit.get("slope_error"))
        qs_text = f"QS = {factor * qs:.4g}" + (f" +- {factor * err_a:.2g}" if err_a > 0 else "")
        k_text = f"k = {factor * k:.4g}" + (f" +- {factor * err_b:.2g}" if err_b > 0 else "")
        text = f"joint fit: QS + k D rate\n{qs_text} {plain}".rstrip() + \
            f"\n{k_text} {plain} s".replace("  ", " ")
        if finite(fit.get("r2")):
            text += f"\nr2 = {fit['r2']:.3f}"
        xs = np.linspace(0.0, xmax, 50)
        ax.plot(xs, factor * (qs + k * xs), "k--", lw=1.0, label=text)
        ax.plot([0.0], [factor * qs], "*", color="tab:red", ms=13, zorder=5,
                label="quasi-static value QS")
    ax.set_xlim(-0.02 * xmax, xmax)
    ax.set_xlabel("damping x axial strain rate, D rate (1/s)")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(f"{label[0].upper() + label[1:]} against D x strain rate")
    if has_inertial:
        for d in dampings:
            sel = ok & (damp == d) & np.isfinite(bias) & np.isfinite(inertial) & (inertial > 0)
            axb.plot(inertial[sel], 100 * bias[sel], "o", color=colours[d], ms=6,
                     label=f"damping {d:g}")
        if finite(tol):
            axb.axhspan(-100 * tol, 100 * tol, color="tab:green", alpha=0.15, lw=0,
                        label=f"tolerance +-{100 * tol:g} %")
        axb.axhline(0.0, color="k", lw=0.6)
        axb.set_xscale("log")
        axb.set_xlabel("inertial number I (-)")
        axb.set_ylabel("rate bias, (value - QS) / QS (%)")
        axb.grid(alpha=0.3, which="both")
        axb.legend(fontsize=7)
        axb.set_title("Rate bias against inertial number")
    save(fig, out, "rate_fit.png", made)
    return made


CALIBRATION_KEYS = ("phi_peak_deg", "cohesion", "young_modulus", "poisson_ratio",
                    "phi_residual_deg")
MICRO_LABELS = {"young": "contact Young's modulus", "kt_over_kn": "kt/kn",
                "friction_deg": "contact friction angle", "normal_cohesion": "normal bond strength",
                "shear_cohesion": "shear bond strength", "rolling_friction": "rolling friction",
                "density": "grain density"}


def plot_calibrate(out, summary, h=None):
    """Calibration: each targeted macro property per iteration against its target,
    with the verification and the upscaled values; the micro parameters and the miss
    per iteration."""
    results = summary.get("results", {})
    if "local_friction_deg" in results:
        from geodem_plot_interface import plot_interface_calibration
        return plot_interface_calibration(out, summary, save)
    made = []
    targets = summary.get("scenario", {}).get("targets", {}) or {}
    iterations = results.get("iterations") or []
    if not iterations:
        table = read_table(out / "calibration.csv")
        if table is not None:
            n = len(next(iter(table.values())))
            iterations = [{"micro": {k: table[k][i] for k in MICRO_LABELS if k in table},
                           "macro": {k: table[k][i] for k in CALIBRATION_KEYS if k in table},
                           "miss": table["miss"][i] if "miss" in table else None}
                          for i in range(n)]
    verification = results.get("verification") or {}
    upscaling = results.get("upscaling") or {}
    n = len(iterations)
    it = np.arange(n)

    def macro_series(key):
        return np.array([number((r.get("macro") or {}).get(key)) for r in iterations])

    keys = [k for k in CALIBRATION_KEYS
            if k in targets or (k in ("phi_peak_deg", "cohesion"))]
    keys = [k for k in keys if np.isfinite(macro_series(k)).any()
            or finite((verification.get("macro") or {}).get(k))
            or finite((upscaling.get("macro") or {}).get(k))]
    micro_keys = []
    for k in MICRO_LABELS:
        v = np.array([number((r.get("micro") or {}).get(k)) for r in iterations])
        v = v[np.isfinite(v)]
        if len(v) >= 2 and np.any(v != 0) and np.ptp(v) > 1e-9 * np.max(np.abs(v)):
            micro_keys.append(k)
    misses = np.array([number(r.get("miss")) for r in iterations])
    panels = len(keys) + (1 if micro_keys else 0) + (1 if np.isfinite(misses).any() else 0)
    if panels == 0:
        return made
    ncols = 2 if panels <= 4 else 3
    nrows = math.ceil(panels / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.6 * ncols, 3.6 * nrows), squeeze=False)
    axes = list(axes.flat)
    for ax in axes[panels:]:
        ax.remove()
    # The verification and the upscaled runs, when done, to the right of the iterations.
    upscale = number(upscaling.get("grain_size_factor"))
    extras = []
    if verification.get("macro"):
        extras.append((verification, "s", "tab:red", "verification", "verif."))
    if upscaling.get("macro"):
        extras.append((upscaling, "D", "tab:purple", "upscaled",
                       f"upscaled\nx{upscale:g}" if finite(upscale) else "upscaled"))
    extras = [(n + 0.5 + j, *e) for j, e in enumerate(extras)]
    shown = [i for i in it if n <= 12 or i % math.ceil(n / 10) == 0]  # readable labels
    tick_pos = shown + [e[0] for e in extras]
    tick_lab = [str(i) for i in shown] + [e[-1] for e in extras]
    x_right = (extras[-1][0] + 0.6) if extras else max(n - 0.5, 0.5)

    def extras_axis(ax):
        ax.set_xticks(tick_pos)
        ax.set_xticklabels(tick_lab, fontsize=8)
        ax.set_xlim(-0.5, x_right)
        ax.set_xlabel("iteration")
        ax.grid(alpha=0.3)

    def iteration_axis(ax):  # search iterations only
        ax.set_xticks(shown)
        ax.set_xlim(-0.5, max(n - 0.5, 0.5))
        ax.set_xlabel("iteration")
        ax.grid(alpha=0.3, which="both")

    checks = verification.get("checks") or {}
    for ax, key in zip(axes, keys):
        label, factor, unit, ylabel = quantity_info(key)
        v = macro_series(key)
        # NaN breaks the line: a missing value shows as a gap.
        ax.plot(it, factor * v, "o-", color="tab:blue", ms=4, lw=1.0, label="search")
        target = number(targets.get(key))
        if finite(target):
            ax.axhline(factor * target, color="k", ls="--", lw=0.9, label="target")
            c = checks.get(key) or {}
            tv = number(c.get("tolerance"))
            if finite(tv):
                # The verification tolerance: relative for the modulus, else absolute.
                half = tv * abs(target) if key == "young_modulus" else tv
                ax.axhspan(factor * (target - half), factor * (target + half), color="tab:green",
                           alpha=0.12, lw=0, label="verification tolerance")
        for x0, block, marker, colour, what, _ in extras:
            m = number((block.get("macro") or {}).get(key))
            if finite(m):
                s = number((block.get("scatter") or {}).get(key), 0.0)
                ax.errorbar([x0], [factor * m], yerr=[factor * s], fmt=marker, color=colour,
                            ms=7, capsize=4, label=f"{what} (+-1 std)")
        met = (checks.get(key) or {}).get("met")
        title = label[0].upper() + label[1:]
        if finite(target):
            title += f": target {factor * target:.4g}"
            title += f" {unit}" if unit not in ("", "-") else ""
        if met is not None:
            title += " (met)" if met else " (not met)"
        ax.set_title(title, fontsize=10)
        ax.set_ylabel(ylabel)
        extras_axis(ax)
        if ax is axes[0]:  # the same markers in every panel
            ax.legend(fontsize=7)
    k = len(keys)
    if micro_keys:
        ax = axes[k]
        k += 1
        cmap = plt.get_cmap("tab10")
        for j, key in enumerate(micro_keys):
            v = np.array([number((r.get("micro") or {}).get(key)) for r in iterations])
            nonzero = v[np.isfinite(v) & (v != 0)]
            ref = nonzero[0]
            r = v / ref
            sel = np.isfinite(r) & (r > 0)
            ax.plot(it[sel], r[sel], "o-", color=cmap(j % 10), ms=4, lw=1.0,
                    label=MICRO_LABELS.get(key, key))
        final = results.get("micro") or {}
        for i, r in enumerate(iterations):
            mic = r.get("micro") or {}
            if final and all(finite(final.get(q)) and finite(mic.get(q)) and
                             math.isclose(final[q], mic[q], rel_tol=1e-9, abs_tol=1e-300)
                             for q in final):
                ax.axvline(i, color="k", ls=":", lw=0.9, label="kept (final material)")
                break
        ax.set_yscale("log")
        ax.set_ylabel("relative to the first (non-zero) value (-)")
        ax.set_title("Micro parameters", fontsize=10)
        iteration_axis(ax)
        ax.legend(fontsize=6)
    if np.isfinite(misses).any():
        ax = axes[k]
        sel = np.isfinite(misses)
        ax.plot(it[sel], misses[sel], "o-", color="tab:gray", ms=4, lw=1.0)
        if (misses[sel] > 0).all() and misses[sel].max() > 20 * misses[sel].min():
            ax.set_yscale("log")
        ax.set_ylabel("miss (search objective, -)")
        ax.set_title("Distance to the targets", fontsize=10)
        iteration_axis(ax)
    state = "converged" if results.get("converged") else "not converged"
    if verification:
        state += ", verification " + ("met" if verification.get("all_met") else "not met")
    fig.suptitle(f"Calibration of the micro parameters ({state})")
    save(fig, out, "calibration.png", made)
    return made


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
