"""Plots of the interface shear test (kind "interface_shear"), used by geodem_plot.py.

Shear stress and the plate's rise against the slip of the sheet, one curve per normal
stress, and the Mohr-Coulomb envelope of the interface (peak and residual).
"""
import math

import matplotlib.pyplot as plt
import numpy as np


def plot_interface_shear(out, summary, h, save):
    made = []
    tests = summary["results"]["tests"]
    test_col = np.asarray(h["test"])
    u = np.asarray(h["displacement"]) * 1e3
    tau = np.asarray(h["shear_stress"]) / 1e3
    rise = np.asarray(h["dilation"]) * 1e3
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True)
    for k, t in enumerate(tests):
        m = test_col == k
        label = f"$\\sigma_n$ = {t['normal_stress_target'] / 1e3:.4g} kPa"
        ax.plot(u[m], tau[m], label=label)
        bx.plot(u[m], rise[m], label=label)
    ax.set_ylabel("shear stress on the sheet (kPa)")
    ax.set_title(f"Interface shear, local friction "
                 f"{summary['results']['local_interface_friction_deg']:.4g} deg")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    bx.set_xlabel("slip of the sheet (mm)")
    bx.set_ylabel("rise of the plate (mm)\n(dilation positive)")
    bx.grid(alpha=0.3)
    save(fig, out, "interface_shear.png", made)

    r = summary["results"]
    sn = np.array([t["normal_stress"] for t in tests]) / 1e3
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for key, env, marker, name in (("peak_shear_stress", "peak_envelope", "o", "peak"),
                                   ("residual_shear_stress", "residual_envelope", "s",
                                    "residual")):
        tau = np.array([t[key] for t in tests]) / 1e3
        e = r[env]
        ax.plot(sn, tau, marker, label=name)
        x = np.linspace(0.0, 1.1 * sn.max(), 20)
        slope = math.tan(math.radians(e["friction_deg"]))
        ax.plot(x, e["adhesion"] / 1e3 + slope * x, "--",
                label=f"{name}: $\\delta$ = {e['friction_deg']:.3g} deg, "
                      f"a = {e['adhesion'] / 1e3:.3g} kPa")
    ax.set_xlabel("normal stress on the sheet (kPa)")
    ax.set_ylabel("shear stress (kPa)")
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    ax.set_title("Interface strength envelope")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out, "interface_envelope.png", made)
    return made


def plot_interface_calibration(out, summary, save):
    """Interface calibration: the macroscopic interface friction of each iteration
    against the sheet's local friction, the target and the verification."""
    made = []
    r = summary["results"]
    target = summary["scenario"]["targets"]["interface_friction_deg"]
    local = [it["local_friction_deg"] for it in r["iterations"]]
    macro = [it["macro"]["interface_friction_deg"] for it in r["iterations"]]
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(local, macro, "o-", label="search iterations (search seeds)")
    for k, (x, y) in enumerate(zip(local, macro)):
        ax.annotate(str(k), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    v = r.get("verification")
    if v:
        scatter = v["scatter"]["interface_friction_deg"]
        ax.errorbar([r["local_friction_deg"]], [v["macro"]["interface_friction_deg"]],
                    yerr=[scatter], fmt="s", color="tab:red", capsize=4,
                    label=f"verification, {v['seeds']} fresh seeds (1 std)")
    ax.axhline(target, color="k", ls="--", lw=1, label=f"target {target:g} deg")
    lo = min(local + macro + [target]) - 3
    hi = max(local + macro + [target]) + 3
    ax.plot([lo, hi], [lo, hi], ":", color="grey", lw=1, label="macro = local")
    ax.set_xlabel("local interface friction of the sheet (deg)")
    ax.set_ylabel("macroscopic interface friction, peak (deg)")
    ax.set_title(f"Interface calibration: local friction {r['local_friction_deg']:.3g} deg")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out, "interface_calibration.png", made)
    return made
