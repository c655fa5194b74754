"""Plots of a calibration of the micro parameters (kind "calibrate"), used by geodem_plot.py.

calibration.png: each targeted macro property per iteration against its target, with the
verification and the upscaled runs; the micro parameters and the miss per iteration. Read
from the summary's results, else from calibration.csv. A calibration of an interface's local
friction is drawn by geodem_plot_interface.py.
"""
import math

import matplotlib.pyplot as plt
import numpy as np
from geodem_plot_tables import finite, number, quantity_info, read_table


CALIBRATION_KEYS = ("phi_peak_deg", "cohesion", "young_modulus", "poisson_ratio",
                    "phi_residual_deg")
MICRO_LABELS = {"young": "contact Young's modulus", "kt_over_kn": "kt/kn",
                "friction_deg": "contact friction angle", "normal_cohesion": "normal bond strength",
                "shear_cohesion": "shear bond strength", "rolling_friction": "rolling friction",
                "density": "grain density"}


def plot_calibrate(out, summary, save):
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

