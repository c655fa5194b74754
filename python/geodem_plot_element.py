"""Plots of the element tests (kinds "isotropic", "oedometer", "simple_shear",
"cyclic_triaxial"), used by geodem_plot.py.

- isotropic, oedometer: void ratio against log stress (the whole path, and its points at
  rest); the oedometer also sigma_h against sigma_v with its K0 on loading.
- simple_shear: shear stress and normal strain against shear strain, one curve per normal
  stress; the stress path tau - sigma_n; the shear envelope of the peaks.
- direct_shear: the same against the upper frame's displacement, with the plate's rise.
- cyclic_triaxial: the measured loop of each amplitude (q against axial strain), and the
  modulus reduction G/Gmax and damping ratio against the shear strain amplitude.
"""
import math

import matplotlib.pyplot as plt
import numpy as np


def plot_stress_steps(out, summary, h, save):
    made = []
    results = summary["results"]
    oedometer = summary["kind"] == "oedometer"
    stress = np.asarray(h["sigma_axial"] if oedometer else h["p"]) / 1e3
    e = np.asarray(h["void_ratio"])
    rest = np.asarray(h["at_rest"]) > 0.5
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.semilogx(stress, e, color="0.6", lw=0.8, label="path")
    ax.semilogx(stress[rest], e[rest], "o-", color="tab:blue", ms=5, label="at rest")
    cc, cs = results.get("compression_index"), results.get("swelling_index")
    text = []
    if cc is not None:
        text.append(f"Cc = {cc:.4g}")
    if cs is not None:
        text.append(f"Cs = {cs:.4g}")
    ax.set_xlabel(("axial stress sigma_v" if oedometer else "mean stress p'") + " (kPa)")
    ax.set_ylabel("void ratio e")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, title=", ".join(text) if text else None)
    ax.set_title("Oedometer: compression and swelling" if oedometer
                 else "Isotropic compression and swelling")
    save(fig, out, "compression.png", made)
    if oedometer:
        sv = np.asarray(h["sigma_axial"]) / 1e3
        sh = np.asarray(h["sigma_lateral"]) / 1e3
        fig, ax = plt.subplots(figsize=(6.0, 4.6))
        ax.plot(sv, sh, color="0.6", lw=0.8, label="path")
        ax.plot(sv[rest], sh[rest], "o-", color="tab:blue", ms=5, label="at rest")
        k0 = results.get("K0_loading")
        if k0 is not None:
            x = np.array([0.0, sv.max()])
            ax.plot(x, sh[rest][0] + k0 * (x - sv[rest][0]), "k--", lw=0.8,
                    label=f"K0 on loading = {k0:.3f}")
        ax.set_xlabel("sigma_v (kPa)")
        ax.set_ylabel("sigma_h (kPa)")
        ax.set_xlim(left=0)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title("Oedometer: lateral against axial stress")
        save(fig, out, "k0.png", made)
    return made


def plot_simple_shear(out, summary, h, save):
    made = []
    results = summary["results"]
    tests = results.get("tests", [])
    box = summary["kind"] == "direct_shear"
    test = np.asarray(h["test"])
    gamma = (1e3 * np.asarray(h["displacement"]) if box
             else 100 * np.asarray(h["shear_strain"]))
    tau = np.asarray(h["shear_stress"]) / 1e3
    sn = np.asarray(h["normal_stress"]) / 1e3
    en = (1e3 * np.asarray(h["vertical_displacement"]) if box
          else 100 * np.asarray(h["normal_strain"]))
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(6.4, 7.0), sharex=True)
    fig_p, px = plt.subplots(figsize=(6.0, 4.6))
    for k in sorted(set(int(t) for t in test)):
        m = test == k
        label = (f"sigma_n = {tests[k]['normal_stress'] / 1e3:.4g} kPa" if k < len(tests)
                 else f"test {k}")
        ax.plot(gamma[m], tau[m], label=label)
        bx.plot(gamma[m], en[m], label=label)
        px.plot(sn[m], tau[m], label=label)
    control = results.get("control", tests[0].get("control", "") if tests else "")
    ax.set_ylabel("shear stress tau (kPa)")
    if box:
        ax.set_title("Direct shear box")
    else:
        ax.set_title("Simple shear" + (", constant volume" if control == "constant_volume"
                                       else ", constant normal stress"))
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    if box:
        bx.set_xlabel("displacement of the upper frame (mm)")
        bx.set_ylabel("rise of the plate (mm, + dilation)")
    else:
        bx.set_xlabel("shear strain gamma (%)")
        bx.set_ylabel("normal strain (%, + contraction)")
        bx.invert_yaxis()
    bx.grid(alpha=0.3)
    save(fig, out, "direct_shear.png" if box else "simple_shear.png", made)
    env = results.get("shear_envelope")
    if env:
        x = np.array([0.0, sn.max()])
        px.plot(x, env["cohesion"] / 1e3 + math.tan(math.radians(env["phi_deg"])) * x, "k--",
                lw=0.8, label=f"peaks: c = {env['cohesion'] / 1e3:.3g} kPa, "
                              f"phi = {env['phi_deg']:.1f} deg")
    px.set_xlabel("normal stress sigma_n (kPa)")
    px.set_ylabel("shear stress tau (kPa)")
    px.set_xlim(left=0)
    px.set_ylim(bottom=0)
    px.grid(alpha=0.3)
    px.legend(fontsize=8)
    px.set_title("Stress path on the " + ("split plane" if box else "shear plane"))
    save(fig_p, out, "stress_path.png", made)
    return made


def plot_cyclic(out, summary, h, save):
    made = []
    results = summary["results"]
    amps = results.get("amplitudes", [])
    amp = np.asarray(h["amplitude"])
    cycle = np.asarray(h["cycle"])
    ea = 100 * np.asarray(h["axial_strain"])
    q = np.asarray(h["q"]) / 1e3
    n = max(1, len(amps))
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.4 * cols, 3.0 * rows), squeeze=False)
    for k in range(n):
        ax = axes[k // cols][k % cols]
        m = amp == k
        if not m.any():
            continue
        last = cycle[m].max() - 1  # the last loop (the row after it returns to zero is cycle max)
        sel = m & (cycle == max(last, 0))
        ax.plot(ea[m], q[m], color="0.75", lw=0.6)
        ax.plot(ea[sel], q[sel], color="tab:blue", lw=1.0)
        if k < len(amps):
            a = amps[k]
            title = (f"q amplitude {a['q_amplitude'] / 1e3:.3g} kPa" if "q_amplitude" in a
                     else f"amplitude {a['axial_strain_amplitude']:.3g}")
        else:
            title = f"{k}"
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
        ax.set_xlabel("axial strain (%)", fontsize=8)
        ax.set_ylabel("q (kPa)", fontsize=8)
    for k in range(n, rows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.suptitle("Cyclic triaxial: loops (the measured one in blue)")
    save(fig, out, "loops.png", made)
    if amps:
        g = [a["shear_strain_amplitude"] for a in amps]
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        ax.semilogx(g, [a["G_over_Gmax"] for a in amps], "o-", color="tab:blue", label="G/Gmax")
        ax.set_xlabel("shear strain amplitude gamma_a")
        ax.set_ylabel("G / Gmax", color="tab:blue")
        ax.set_ylim(0, 1.1)
        ax.grid(alpha=0.3, which="both")
        bx = ax.twinx()
        bx.semilogx(g, [100 * a["damping_ratio"] for a in amps], "s--", color="tab:red",
                    label="damping")
        bx.set_ylabel("damping ratio D (%)", color="tab:red")
        bx.set_ylim(bottom=0)
        ax.set_title(f"Modulus reduction and damping (Gmax = "
                     f"{results.get('shear_modulus_max', 0) / 1e6:.4g} MPa)")
        save(fig, out, "modulus_damping.png", made)
    return made
