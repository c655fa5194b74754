#!/usr/bin/env python3
"""The element tests of one dense disc soil, seeds 1 to N (two runs at a time): friction
from the biaxial (periodic cell), simple-shear and direct-shear tests side by side, K0 from
the oedometer beside Jaky's 1 - sin(phi), compression indices, and the modulus reduction and
damping curves of the cyclic test.

    examples/lab2d/consistency.py OUT [--seeds 5] [--soil discs|sand_2d]
                                      [--geodem build/geodem] [--reuse]

--soil discs (the default) runs the scenarios of this folder as they are; --soil sand_2d runs
them on the shipped sand preset instead (two-disc clumps with rolling resistance, calibrated
for the pull-out examples: presets/sand_2d.toml) at its stresses, a fifth of the discs' (10,
20, 40 kPa; 20 kPa of compaction and cyclic confinement; oedometer and isotropic steps 40 kPa
to 320 kPa and back to 20 kPa), prepared to the preset's porosity. The scenarios run are
written to OUT/scenarios/.

Writes OUT/consistency.md (the tables of the README), OUT/consistency.json and the figures
OUT/modulus_damping.png and OUT/compression.png (copied to expected/ by
scripts/refresh-examples.sh --all).
"""
import argparse
import json
import math
import re
import statistics
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = Path(__file__).resolve().parent
KINDS = ["biaxial", "simple_shear", "direct_shear", "oedometer", "isotropic", "cyclic"]


def scenario_text(kind, soil):
    """The scenario of `kind` for the soil: this folder's file, or the same test on a preset
    at a fifth of the stresses."""
    text = (HERE / f"{kind}.toml").read_text()
    if soil == "discs":
        return text
    head, rest = text.split("[material]\n", 1)
    rest = rest.split("\n\n", 1)[1]  # the disc material's keys, up to the blank line
    text = head + f'[material]\npreset = "{soil}"\n\n' + rest
    # The preset's grain shape, size spread and porosity.
    text = re.sub(r"target_porosity = .*\n", "", text)
    text = re.sub(r"radius_fuzz = .*\n", "", text)
    text = f"# {kind}.toml of examples/lab2d on the preset {soil}, at a fifth of the stresses\n" + text

    def scaled(m):
        return m.group(1) + re.sub(r"[0-9.]+e[0-9]+", lambda v: f"{float(v.group(0)) / 5:g}",
                                   m.group(2))
    return re.sub(r"^((?:confining_stress|normal_stress|stresses) = )(.*)$", scaled, text,
                  flags=re.M)


def run(geodem, scenario, out, seed, reuse, soil):
    path = out.parent / "scenarios" / f"{scenario}.toml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(scenario_text(scenario, soil))
    if not reuse or not (out / "summary.json").exists():
        subprocess.run([geodem, "run", str(path), "--out", str(out),
                        "--overwrite", "--quiet", "--threads", "1", "--set", f"seed={seed}",
                        "--set", "output.plots=false"], check=True)
    return json.loads((out / "summary.json").read_text())


def ms(values):
    """Mean and sample standard deviation (0 for one value)."""
    v = [x for x in values if x is not None]
    return statistics.mean(v), (statistics.stdev(v) if len(v) > 1 else 0.0)


def fmt(pair, digits=1):
    return f"{pair[0]:.{digits}f} +- {pair[1]:.{digits}f}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--soil", default="discs", help="discs, or a preset name (sand_2d)")
    ap.add_argument("--geodem", default="build/geodem")
    ap.add_argument("--reuse", action="store_true", help="read the runs already in OUT")
    a = ap.parse_args()
    out = Path(a.out)
    seeds = list(range(1, a.seeds + 1))
    jobs = [(k, s) for k in KINDS for s in seeds]
    with ThreadPoolExecutor(2) as pool:
        done = list(pool.map(lambda j: run(a.geodem, j[0], out / f"{j[0]}_seed{j[1]}", j[1],
                                           a.reuse, a.soil), jobs))
    res = {k: [] for k in KINDS}
    wall = {k: [] for k in KINDS}
    for (k, _), summary in zip(jobs, done):
        res[k].append(summary["results"])
        wall[k].append(summary["timing"]["wall_s"])

    def per_test(kind, key):
        return ms([t[key] for r in res[kind] for t in r["tests"]])

    table = {}
    bi_peak, bi_res = per_test("biaxial", "phi_peak_deg"), per_test("biaxial", "phi_residual_deg")
    table["biaxial"] = {"envelope_phi": ms([r["mohr_coulomb"]["phi_deg"] for r in res["biaxial"]]),
                        "peak": bi_peak, "residual": bi_res}
    table["simple_shear"] = {
        "envelope_phi": ms([r["shear_envelope"]["phi_deg"] for r in res["simple_shear"]]),
        "peak": per_test("simple_shear", "phi_plane_peak_deg"),
        "residual": per_test("simple_shear", "phi_plane_residual_deg"),
        "peak_principal": per_test("simple_shear", "phi_mobilised_peak_deg"),
        "residual_principal": per_test("simple_shear", "phi_mobilised_residual_deg"),
        "dilatancy": per_test("simple_shear", "dilatancy_deg"),
        "corrected": per_test("simple_shear", "phi_peak_dilatancy_corrected_deg")}
    table["direct_shear"] = {
        "envelope_phi": ms([r["shear_envelope"]["phi_deg"] for r in res["direct_shear"]]),
        "peak": per_test("direct_shear", "phi_peak_deg"),
        "residual": per_test("direct_shear", "phi_residual_deg"),
        "dilatancy": per_test("direct_shear", "dilatancy_deg"),
        "corrected": per_test("direct_shear", "phi_peak_dilatancy_corrected_deg")}
    n = len(seeds)
    kpa = (lambda x: f"{x / 1e3 / (1 if a.soil == 'discs' else 5):g}")  # the soil's stresses
    soil = ("dense disc soil (1,000 discs, contact friction 0.5)" if a.soil == "discs"
            else f"preset {a.soil} (1,000 grains)")
    lines = [f"The {soil}, {n} seeds, 3 normal or confining stresses ({kpa(5e4)}, {kpa(1e5)}, "
             f"{kpa(2e5)} kPa) each: mean +- standard deviation over the {3 * n} tests "
             f"(envelopes: over the {n} seeds).", "",
             "| test | envelope phi (deg) | peak phi (deg) | residual phi (deg) | dilatancy at "
             "the peak (deg) | peak phi less dilatancy (deg) |",
             "| --- | ---: | ---: | ---: | ---: | ---: |",
             f"| biaxial, periodic cell (Mohr circles) | {fmt(table['biaxial']['envelope_phi'])} "
             f"| {fmt(bi_peak)} | {fmt(bi_res)} | | |"]
    ss, ds = table["simple_shear"], table["direct_shear"]
    lines.append(f"| simple shear, principal stresses | | {fmt(ss['peak_principal'])} | "
                 f"{fmt(ss['residual_principal'])} | | |")
    lines.append(f"| simple shear, tau / sigma_n on the horizontal plane | "
                 f"{fmt(ss['envelope_phi'])} | {fmt(ss['peak'])} | {fmt(ss['residual'])} | "
                 f"{fmt(ss['dilatancy'])} | {fmt(ss['corrected'])} |")
    lines.append(f"| direct shear box, tau / sigma_n | {fmt(ds['envelope_phi'])} | "
                 f"{fmt(ds['peak'])} | {fmt(ds['residual'])} | {fmt(ds['dilatancy'])} | "
                 f"{fmt(ds['corrected'])} |")

    # K0 beside Jaky's 1 - sin(phi), with the biaxial peak and residual angles.
    k0 = ms([r["K0_loading"] for r in res["oedometer"]])
    k0_top = ms([r["K0_at_largest_stress"] for r in res["oedometer"]])
    jaky_peak = 1 - math.sin(math.radians(bi_peak[0]))
    jaky_res = 1 - math.sin(math.radians(bi_res[0]))
    table["oedometer"] = {"K0_loading": k0, "K0_at_largest_stress": k0_top,
                          "jaky_peak": jaky_peak, "jaky_residual": jaky_res,
                          "Cc": ms([r["compression_index"] for r in res["oedometer"]]),
                          "Cs": ms([r["swelling_index"] for r in res["oedometer"]])}
    table["isotropic"] = {"Cc": ms([r["compression_index"] for r in res["isotropic"]]),
                          "Cs": ms([r["swelling_index"] for r in res["isotropic"]])}
    lines += ["", f"| K0 on loading (slope of sigma_h on sigma_v) | K0 at {kpa(1.6e6)} kPa | Jaky 1 - sin(phi), "
              "biaxial peak phi | Jaky, biaxial residual phi |", "| ---: | ---: | ---: | ---: |",
              f"| {fmt(k0, 3)} | {fmt(k0_top, 3)} | {jaky_peak:.3f} | {jaky_res:.3f} |", "",
              "| test | compression index Cc | swelling index Cs |", "| --- | ---: | ---: |",
              f"| oedometer (e against log10 sigma_v) | {fmt(table['oedometer']['Cc'], 4)} | "
              f"{fmt(table['oedometer']['Cs'], 4)} |",
              f"| isotropic (e against log10 p') | {fmt(table['isotropic']['Cc'], 4)} | "
              f"{fmt(table['isotropic']['Cs'], 4)} |"]

    # Cyclic: each amplitude's mean over the seeds.
    amps = [x["axial_strain_amplitude"] for x in res["cyclic"][0]["amplitudes"]]
    cyc = []
    for i, amp in enumerate(amps):
        pts = [r["amplitudes"][i] for r in res["cyclic"]]
        cyc.append({"axial_strain_amplitude": amp,
                    "shear_strain_amplitude": ms([p["shear_strain_amplitude"] for p in pts]),
                    "G_over_Gmax": ms([p["G_over_Gmax"] for p in pts]),
                    "damping_ratio": ms([p["damping_ratio"] for p in pts])})
    gmax = ms([r["shear_modulus_max"] for r in res["cyclic"]])
    table["cyclic"] = {"Gmax": gmax, "amplitudes": cyc}
    lines += ["", f"Cyclic biaxial loading at {kpa(1e5)} kPa: Gmax = {gmax[0] / 1e6:.1f} +- "
              f"{gmax[1] / 1e6:.1f} MPa (the secant modulus at the smallest amplitude).", "",
              "| axial strain amplitude | shear strain amplitude | G / Gmax | damping ratio (%) |",
              "| ---: | ---: | ---: | ---: |"]
    for c in cyc:
        lines.append(f"| {c['axial_strain_amplitude']:.0e} | {c['shear_strain_amplitude'][0]:.2e} | "
                     f"{fmt(c['G_over_Gmax'], 3)} | {100 * c['damping_ratio'][0]:.2f} +- "
                     f"{100 * c['damping_ratio'][1]:.2f} |")
    lines += ["", "Wall time per run (s, one thread): " + ", ".join(
        f"{k} {statistics.mean(wall[k]):.0f}" for k in KINDS)]
    table["wall_s"] = {k: statistics.mean(wall[k]) for k in KINDS}
    (out / "consistency.md").write_text("\n".join(lines) + "\n")
    (out / "consistency.json").write_text(json.dumps(table, indent=1))
    print("\n".join(lines))

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    g = [c["shear_strain_amplitude"][0] for c in cyc]
    ax.errorbar(g, [c["G_over_Gmax"][0] for c in cyc], yerr=[c["G_over_Gmax"][1] for c in cyc],
                fmt="o-", color="tab:blue", capsize=3, label="G / Gmax")
    ax.set_xscale("log")
    ax.set_ylim(0, 1.1)
    ax.set_xlabel("shear strain amplitude gamma_a")
    ax.set_ylabel("G / Gmax", color="tab:blue")
    ax.grid(alpha=0.3, which="both")
    bx = ax.twinx()
    bx.errorbar(g, [100 * c["damping_ratio"][0] for c in cyc],
                yerr=[100 * c["damping_ratio"][1] for c in cyc], fmt="s--", color="tab:red",
                capsize=3, label="damping")
    bx.set_ylabel("damping ratio D (%)", color="tab:red")
    bx.set_ylim(bottom=0)
    ax.set_title(f"Cyclic biaxial, {kpa(1e5)} kPa, {soil.split(' (')[0]}, {n} seeds (mean +- std)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "modulus_damping.png", dpi=120)

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9.6, 4.0), sharey=True)
    for kind, axis, measure in (("oedometer", ax, "sigma_axial"), ("isotropic", bx, None)):
        for r in res[kind]:
            pts = r["points"]
            s = [p["sigma_axial"] if measure else (p["sigma_axial"] + p["sigma_lateral"]) / 2
                 for p in pts]
            axis.semilogx([x / 1e3 for x in s], [p["void_ratio"] for p in pts], "o-", ms=3, lw=0.8)
        axis.set_xlabel("sigma_v (kPa)" if measure else "p' (kPa)")
        axis.grid(alpha=0.3, which="both")
        axis.set_title(f"{kind}: Cc = {table[kind]['Cc'][0]:.4f}, Cs = {table[kind]['Cs'][0]:.4f}",
                       fontsize=9)
    ax.set_ylabel("void ratio e")
    fig.suptitle(f"Compression and swelling, {n} seeds")
    fig.tight_layout()
    fig.savefig(out / "compression.png", dpi=120)


if __name__ == "__main__":
    main()
