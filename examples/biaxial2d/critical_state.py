#!/usr/bin/env python3
"""Drained and undrained biaxial tests of the example's dense disc sample in a periodic
cell, at its three confining stresses, seeds 1 to N (two runs at a time), sheared to a large
strain: the critical state line q = M p' from the drained tests' ends, and where the undrained
(constant-volume) stress paths end against it; the same line in the e - log p' plane.

    examples/biaxial2d/critical_state.py OUT [--seeds 3] [--strain 0.25] [--count 2000]
                                         [--geodem build/geodem] [--reuse]

Writes OUT/critical_state.md (the table of the README), OUT/critical_state.json and
OUT/critical_state.png (copied to expected/ by scripts/refresh-examples.sh --all).
"""
import argparse
import csv
import json
import math
import statistics
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
REUSE = False  # --reuse: runs already in OUT are read, not run again


def run(geodem, out, drainage, seed, strain, count):
    if not REUSE or not (out / "summary.json").exists():
        subprocess.run([geodem, "run", str(HERE / "scenario.toml"), "--out", str(out), "--overwrite",
                        "--quiet", "--threads", "1", "--set", f"seed={seed}",
                        "--set", "sample.boundary=periodic", "--set", f"shear.drainage={drainage}",
                        "--set", f"shear.max_axial_strain={strain}", "--set", "output.vtk=false",
                        "--set", f"sample.count={count}",
                        "--set", f"sample.box=[1.0, {2.0 * count / 2000}]"],
                       check=True)
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "history.csv") as f:
        rows = list(csv.DictReader(f))
    return summary["results"]["tests"], rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--strain", type=float, default=0.25)
    ap.add_argument("--count", type=int, default=2000, help="discs (the box keeps their size)")
    ap.add_argument("--geodem", default="build/geodem")
    ap.add_argument("--reuse", action="store_true", help="read the runs already in OUT")
    a = ap.parse_args()
    global REUSE
    REUSE = a.reuse
    out = Path(a.out)
    jobs = [(d, s) for d in ("drained", "undrained") for s in range(1, a.seeds + 1)]
    with ThreadPoolExecutor(2) as pool:
        done = list(pool.map(lambda j: run(a.geodem, out / f"{j[0]}_seed{j[1]}", j[0], j[1],
                                           a.strain, a.count), jobs))
    # The stress ratio at the end of each drained test: the critical state's M.
    ends = {"drained": [], "undrained": []}
    for (drainage, seed), (tests, _) in zip(jobs, done):
        for t in tests:
            ends[drainage].append({"seed": seed, "sigma3": t["confining_stress"], "p": t["p_end"],
                                   "q": t["q_end"], "M": t["stress_ratio_end"],
                                   "u_end": t.get("excess_pore_pressure_end", 0.0)})
    m_drained = [e["M"] for e in ends["drained"]]
    M, M_std = statistics.mean(m_drained), statistics.stdev(m_drained)
    lines = [f"Drained tests' stress ratio at {100 * a.strain:g} % axial strain: M = {M:.3f} +- "
             f"{M_std:.3f} (mean +- std of {len(m_drained)} tests: {a.seeds} seeds x 3 stresses)",
             "",
             "| sigma3 (kPa) | drained p' (kPa) | drained q (kPa) | drained M | undrained p' (kPa) "
             "| undrained q (kPa) | undrained M | (M_u - M) / std of drained M | excess pore "
             "pressure at the end (kPa) |",
             "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    table = {"M": M, "M_std": M_std, "stresses": []}
    for s3 in sorted({e["sigma3"] for e in ends["drained"]}):
        def stats(kind, key):
            v = [e[key] for e in ends[kind] if e["sigma3"] == s3]
            return statistics.mean(v), statistics.stdev(v) if len(v) > 1 else 0.0
        row = {k: {q: stats(k, q) for q in ("p", "q", "M", "u_end")} for k in ends}
        table["stresses"].append({"sigma3": s3, **row})
        d, u = row["drained"], row["undrained"]
        lines.append(
            f"| {s3 / 1e3:g} | {d['p'][0] / 1e3:.0f} +- {d['p'][1] / 1e3:.0f} | "
            f"{d['q'][0] / 1e3:.0f} +- {d['q'][1] / 1e3:.0f} | {d['M'][0]:.3f} +- {d['M'][1]:.3f} | "
            f"{u['p'][0] / 1e3:.0f} +- {u['p'][1] / 1e3:.0f} | {u['q'][0] / 1e3:.0f} +- "
            f"{u['q'][1] / 1e3:.0f} | {u['M'][0]:.3f} +- {u['M'][1]:.3f} | "
            f"{(u['M'][0] - M) / M_std:+.1f} | {u['u_end'][0] / 1e3:.0f} +- {u['u_end'][1] / 1e3:.0f} |")
    # The critical state line in the void ratio - log p' plane: e = Gamma - lambda log10(p' / 1 kPa)
    # by least squares over the drained tests' ends (their last row), and the undrained ends'
    # distance from it in standard deviations of the drained points about the line.
    ends_e = {"drained": [], "undrained": []}
    for (drainage, seed), (tests, rows) in zip(jobs, done):
        for t in range(len(tests)):
            last = [r for r in rows if int(float(r["test"])) == t][-1]
            n = float(last["porosity"])
            ends_e[drainage].append((math.log10(float(last["p"]) / 1e3), n / (1.0 - n)))
    xs, es = zip(*ends_e["drained"])
    mx, me = statistics.mean(xs), statistics.mean(es)
    lam = -sum((x - mx) * (e - me) for x, e in zip(xs, es)) / sum((x - mx) ** 2 for x in xs)
    gamma = me + lam * mx
    spread = statistics.stdev([e - (gamma - lam * x) for x, e in zip(xs, es)])
    off = [(e - (gamma - lam * x)) / spread for x, e in ends_e["undrained"]]
    table["csl_e_log_p"] = {"Gamma": gamma, "lambda10": lam, "residual_std": spread,
                            "undrained_offsets_in_std": off}
    lines += ["", f"Critical state line in e - log p' (drained ends): e = {gamma:.4f} - "
              f"{lam:.4f} log10(p' / 1 kPa), scatter of the drained ends about it {spread:.4f}; "
              f"undrained ends (e = {statistics.mean(e for _, e in ends_e['undrained']):.4f}, "
              f"p' = {statistics.mean(10 ** x for x, _ in ends_e['undrained']):.0f} kPa on "
              f"average) lie {statistics.mean(off):+.1f} +- {statistics.stdev(off):.1f} such "
              "standard deviations from it (the line extrapolated from the drained range)."]
    (out / "critical_state.md").write_text("\n".join(lines) + "\n")
    (out / "critical_state.json").write_text(json.dumps(table, indent=1))
    print("\n".join(lines))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5))
    colours = {5e4: "tab:blue", 1e5: "tab:green", 2e5: "tab:red"}
    pmax = 0.0
    for (drainage, seed), (tests, rows) in zip(jobs, done):
        for t, s3 in enumerate(sorted(colours)):
            sel = [r for r in rows if int(float(r["test"])) == t]
            p = [float(r["p"]) / 1e3 for r in sel]
            pmax = max(pmax, max(p))
            ax.plot(p, [float(r["q"]) / 1e3 for r in sel], color=colours[s3], lw=0.8,
                    ls="--" if drainage == "drained" else "-",
                    label=f"{drainage}, sigma3 = {s3 / 1e3:g} kPa" if seed == 1 else None)
    ax.plot([0, pmax], [0, M * pmax], "k", lw=1.5, label=f"drained ends: q = {M:.3f} p'")
    ax.set_xlabel("p' (kPa)")
    ax.set_ylabel("q (kPa)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=7)
    ax.set_title(f"{a.count} discs, periodic cell, seeds 1-{a.seeds}: drained (dashed), "
                 "undrained (solid)")
    for drainage, marker in (("drained", "o"), ("undrained", "s")):
        bx.semilogx([10 ** x for x, _ in ends_e[drainage]], [e for _, e in ends_e[drainage]],
                    marker, label=f"{drainage} ends")
    px = [10 ** min(xs) * 0.8, 10 ** max(x for x, _ in ends_e["undrained"]) * 1.2]
    bx.semilogx(px, [gamma - lam * math.log10(p) for p in px], "k", lw=1.2,
                label=f"e = {gamma:.3f} - {lam:.4f} log10 p'")
    bx.set_xlabel("p' (kPa)")
    bx.set_ylabel("void ratio e")
    bx.grid(alpha=0.3, which="both")
    bx.legend(fontsize=7)
    bx.set_title("Critical state line, e - log p'")
    fig.tight_layout()
    fig.savefig(out / "critical_state.png", dpi=110)


if __name__ == "__main__":
    main()
