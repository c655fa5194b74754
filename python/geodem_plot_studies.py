"""Plots of the studies of a value over many runs (kinds "series" and "rate_study"), used by
geodem_plot.py. Studies write no history.csv: these read the summary's results and the runs'
table (runs.csv).

- series: the representativeness of the sample size: the value against d0/L with the fit
  extrapolated to an infinite sample, its bias against the grain count
  (representativeness_mean.png), and its standard deviation against d0/L
  (representativeness_std.png).
- rate_study: the value against strain rate per damping coefficient (rate_effect.png), and
  against damping x strain rate with the joint fit value = QS + k D rate, beside the rate
  bias against the inertial number (rate_fit.png).
"""
import matplotlib.pyplot as plt
import numpy as np
from geodem_plot_tables import finite, fit_text, number, quantity_info, read_table


def plot_series(out, summary, save):
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


def plot_rate_study(out, summary, save):
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

