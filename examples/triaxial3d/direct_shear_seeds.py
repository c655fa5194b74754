#!/usr/bin/env python3
"""The 3D direct shear box (direct_shear.toml), seeds 1 to N, two runs at a time: prints the
table of the README (mean and standard deviation over the seeds of each normal stress's peak
and residual friction and dilatancy, and of the envelopes) and draws every seed's shear stress
and plate rise against the displacement.

    examples/triaxial3d/direct_shear_seeds.py OUT [--seeds 3] [--geodem build/geodem]
                                                  [--reuse] [--set KEY=VALUE ...]

Writes OUT/direct_shear.md, OUT/direct_shear.json and OUT/direct_shear_seeds.png (copied to
expected/ by scripts/refresh-examples.sh --all).
"""
import json
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from compare_boundaries import mean_std, run, seed_arguments

HERE = Path(__file__).resolve().parent


def fmt(values, digits=1):
    m, s = mean_std(values)
    return f"{m:.{digits}f} +- {s:.{digits}f}"


def main():
    ap = seed_arguments()
    ap.add_argument("--set", action="append", default=[], help="passed on to every run")
    a = ap.parse_args()
    out = Path(a.out)
    seeds = list(range(1, a.seeds + 1))
    with ThreadPoolExecutor(2) as pool:
        runs = list(pool.map(lambda s: run(a.geodem, HERE / "direct_shear.toml", out / f"seed{s}", s,
                                           a.reuse, a.set), seeds))
    results = [r["results"] for r, _ in runs]
    stresses = [t["normal_stress"] for t in results[0]["tests"]]
    lines = [f"3D direct shear box, {len(seeds)} seeds (mean +- std):", "",
             "| normal stress (kPa) | peak phi (deg) | residual phi (deg) | dilatancy at the peak "
             "(deg) | peak phi less dilatancy (deg) | displacement at the peak (mm) |",
             "| ---: | ---: | ---: | ---: | ---: | ---: |"]
    table = []
    for i, sn in enumerate(stresses):
        tests = [r["tests"][i] for r in results]
        row = {k: [t[k] for t in tests] for k in ("phi_peak_deg", "phi_residual_deg",
                                                 "dilatancy_deg",
                                                 "phi_peak_dilatancy_corrected_deg",
                                                 "displacement_at_peak", "grains_outside_box")}
        table.append({"normal_stress": sn, **row})
        lines.append(f"| {sn / 1e3:.0f} | {fmt(row['phi_peak_deg'])} | "
                     f"{fmt(row['phi_residual_deg'])} | {fmt(row['dilatancy_deg'])} | "
                     f"{fmt(row['phi_peak_dilatancy_corrected_deg'])} | "
                     f"{fmt([1e3 * d for d in row['displacement_at_peak']], 0)} |")
    env = [r["shear_envelope"] for r in results]
    outside = sum(sum(t["grains_outside_box"]) for t in table)
    walls = [r["timing"]["wall_s"] for r, _ in runs]
    lines += ["", f"Envelope over the normal stresses: peak phi = {fmt([e['phi_deg'] for e in env])} "
              f"deg, c = {fmt([e['cohesion'] / 1e3 for e in env])} kPa; residual phi = "
              f"{fmt([e['residual_phi_deg'] for e in env])} deg, c = "
              f"{fmt([e['residual_cohesion'] / 1e3 for e in env])} kPa. Grains outside the "
              f"frames: {outside}. Wall time per run: {fmt(walls, 0)} s (one thread, two runs "
              f"side by side)."]
    text = "\n".join(lines) + "\n"
    (out / "direct_shear.md").write_text(text)
    (out / "direct_shear.json").write_text(json.dumps(
        {"seeds": seeds, "tests": table, "envelopes": env, "wall_s": walls}, indent=1))
    print(text)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for seed, (_, rows) in zip(seeds, runs):
        for i, sn in enumerate(stresses):
            test = [r for r in rows if int(float(r["test"])) == i]
            u = [1e3 * float(r["displacement"]) for r in test]
            label = f"{sn / 1e3:.0f} kPa" if seed == seeds[0] else None
            ax1.plot(u, [float(r["shear_stress"]) / 1e3 for r in test], color=colours[i],
                     lw=1, alpha=0.8, label=label)
            ax2.plot(u, [1e3 * float(r["vertical_displacement"]) for r in test],
                     color=colours[i], lw=1, alpha=0.8)
    ax1.set_ylabel("shear stress tau (kPa)")
    ax1.set_title(f"3D direct shear box, seeds {seeds[0]}-{seeds[-1]}")
    ax1.legend(title="normal stress")
    ax2.set_ylabel("rise of the plate (mm, + dilation)")
    ax2.set_xlabel("displacement of the upper frame (mm)")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "direct_shear_seeds.png", dpi=110)


if __name__ == "__main__":
    main()
