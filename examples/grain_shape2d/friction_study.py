#!/usr/bin/env python3
"""Peak friction angle against contact friction for discs and for the paper's 2-disc
clumps (radii ratio 0.9), without and with rolling resistance, in dense 2D biaxial
tests at one porosity (the analogue of the paper's figure 9).

    python3 examples/grain_shape2d/friction_study.py [OUT_DIR] [--jobs N] [--quick]

Writes OUT_DIR/friction_study.csv, friction_table.md and friction_study.png
(default OUT_DIR: out/grain_shape2d/friction). About 10 minutes on two cores.
"""
import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent / "python"))
import geodem_study  # noqa: E402

FRICTIONS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
VARIANTS = [  # label, grain, rolling friction
    ("discs", "disc", 0.0),
    ("discs + rolling 0.1", "disc", 0.1),
    ("clumps", "pair_0.9", 0.0),
    ("clumps + rolling 0.1", "pair_0.9", 0.1),
]
POROSITY = 0.17


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?", default="out/grain_shape2d/friction")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="three friction values only")
    a = ap.parse_args()
    frictions = [0.1, 0.5, 1.0] if a.quick else FRICTIONS
    base = (HERE / "base.toml").read_text()
    out = Path(a.out)
    cases, keys = [], []
    for label, grain, rolling in VARIANTS:
        for mu in frictions:
            text = base.format(seed=1, grain=grain, friction=mu, rolling=rolling, cohesion=0.0,
                               porosity=POROSITY, confining="[1e5]")
            cases.append((out / f"{grain}_roll{rolling}_mu{mu}", text))
            keys.append((label, mu))
    summaries = geodem_study.run_cases(cases, a.jobs)
    table = {}
    with open(out / "friction_study.csv", "w") as f:
        f.write("variant,contact_friction,porosity,phi_peak_deg,phi_residual_deg,wall_s\n")
        for (label, mu), s in zip(keys, summaries):
            r = s["results"]
            table[(label, mu)] = r
            f.write(f"{label},{mu},{r['porosity_initial']:.4f},{r['phi_peak_deg']:.2f},"
                    f"{r['phi_residual_deg']:.2f},{s['timing']['wall_s']:.1f}\n")
    labels = [v[0] for v in VARIANTS]
    with open(out / "friction_table.md", "w") as f:
        f.write("Peak friction angle (deg) of dense 2D samples (1000 grains, porosity "
                f"{POROSITY}, confining stress 100 kPa); residual angle in brackets.\n\n")
        f.write("| contact friction | " + " | ".join(labels) + " |\n")
        f.write("|---|" + "---|" * len(labels) + "\n")
        for mu in frictions:
            cells = [f"{table[(l, mu)]['phi_peak_deg']:.1f} ({table[(l, mu)]['phi_residual_deg']:.1f})"
                     for l in labels]
            f.write(f"| {mu} | " + " | ".join(cells) + " |\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for label in labels:
        ax.plot(frictions, [table[(label, mu)]["phi_peak_deg"] for mu in frictions], "o-",
                label=label)
    ax.set_xlabel("contact friction coefficient")
    ax.set_ylabel("peak friction angle (deg)")
    ax.set_title(f"Dense 2D biaxial tests, porosity {POROSITY}")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "friction_study.png", dpi=120)
    print((out / "friction_table.md").read_text())


if __name__ == "__main__":
    main()
