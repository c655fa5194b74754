#!/usr/bin/env python3
"""Benchmark B5: geodem against LAMMPS (Debian's `lammps`, GRANULAR package) on B2's settle
and dense bed, run side by side, one after the other, one thread / one process each.

usage: run_b5.py [--with-peers] [--n 20000 200000] [--laws hooke hertz] [--settle 50000]
                 [--dense 10000] [--out benchmarks/results/b5] [--geodem build/geodem]

For each N and law: writes B2's lattice start (../b2_settle3d/liggghts_input.py), geodem's
scenario (../b2_settle3d/geodem_scenario.py; for Hertz its materials switched to the
Hertz-Mindlin law with Y = 5 MPa, nu = 0.25) and LAMMPS' input (lammps_input.py), runs both
under /usr/bin/time -v and prints one markdown table: wall seconds, particle-steps/s while
settling and on the settled bed (LAMMPS' "Loop time" of each run; geodem's history wall
clock), peak RSS, the bed's top centre, and geodem/LAMMPS ratios.
"""
import argparse
import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE.parent / "b2_settle3d"))
from run_b2 import time_geodem, time_v  # noqa: E402


def hertz_scenario(hooke_toml, path):
    """geodem's B2 scenario with the Hertz-Mindlin law instead of constant Hooke springs."""
    text = Path(hooke_toml).read_text()
    text = re.sub(r"\[\[pairs\]\]\nmaterials = \[\"glass\", \"wall\"\]\nkn = [\d.e+-]+\nkt = [\d.e+-]+\n", "",
                  text)
    text = re.sub(r"\nkn = [\d.e+-]+\nkt = [\d.e+-]+\n", "\nlaw = \"hertz\"\nyoung = 5e6\npoisson = 0.25\n",
                  text)
    Path(path).write_text(text)


def run_lammps(folder, law, n, settle, dense):
    wall, rss, out = time_v(["lmp", "-in", f"in.{law}", "-log", f"log.{law}"], cwd=folder)
    loops = [float(t) for t in re.findall(r"Loop time of ([\d.eE+-]+) on", out)]
    if len(loops) != 2:
        sys.exit(f"LAMMPS printed {len(loops)} loop times:\n{out[-3000:]}")
    zmax = None
    for line in out.splitlines():  # the last thermo row: step atoms ke rke zmax cpu
        f = line.split()
        if len(f) == 6 and f[0].isdigit() and int(f[0]) == settle + dense:
            zmax = float(f[4])
    return {"wall": wall, "settle_ps": n * settle / loops[0], "dense_ps": n * dense / loops[1],
            "rss_kb": rss, "top": zmax}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--with-peers", action="store_true", help="install LAMMPS first")
    ap.add_argument("--n", type=int, nargs="+", default=[20000])
    ap.add_argument("--laws", nargs="+", default=["hooke", "hertz"], choices=["hooke", "hertz"])
    ap.add_argument("--settle", type=int, default=50000)
    ap.add_argument("--dense", type=int, default=10000)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "b5"))
    ap.add_argument("--geodem", default=str(ROOT / "build" / "geodem"))
    a = ap.parse_args()
    if a.with_peers:
        subprocess.run([str(ROOT / "scripts" / "install-deps.sh"), "--with-peers"], check=True)
    b2 = HERE.parent / "b2_settle3d"
    print("| N | law | code | wall s | settle Mps/s | dense Mps/s | peak RSS MB | bed top m | "
          "ratio settle | ratio dense | ratio memory |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in a.n:
        out = Path(a.out) / f"n{n}"
        out.mkdir(parents=True, exist_ok=True)
        side = 0.4 * max(1.0, n / 20000.0) ** 0.5
        subprocess.run([sys.executable, str(b2 / "liggghts_input.py"), "-n", str(n), "-o", str(out),
                        "--settle-steps", str(a.settle), "--dense-steps", str(a.dense)],
                       check=True, capture_output=True)
        subprocess.run([sys.executable, str(b2 / "geodem_scenario.py"), str(n), str(out), "--settle",
                        str(a.settle), "--dense", str(a.dense)], check=True)
        for law in a.laws:
            scenario = out / "settle3d.toml"
            if law == "hertz":
                scenario = out / "settle3d_hertz.toml"
                hertz_scenario(out / "settle3d.toml", scenario)
            subprocess.run([sys.executable, str(HERE / "lammps_input.py"), str(out), "--law", law,
                            "--lx", str(side), "--settle", str(a.settle), "--dense", str(a.dense)],
                           check=True)
            g = time_geodem(a.geodem, scenario, out / f"geodem_{law}", n, 3, a.settle)
            print(f"geodem {law} N={n}: {g}", file=sys.stderr)
            lmp = run_lammps(out, law, n, a.settle, a.dense)
            print(f"LAMMPS {law} N={n}: {lmp}", file=sys.stderr)
            for code, r in (("geodem", g), ("LAMMPS", lmp)):
                ratio = ("", "", "")
                if code == "geodem":
                    ratio = (f"{g['settle_ps'] / lmp['settle_ps']:.2f}", f"{g['dense_ps'] / lmp['dense_ps']:.2f}",
                             f"{g['rss_kb'] / lmp['rss_kb']:.2f}")
                top = f"{r['top']:.4f}" if r["top"] is not None else "?"
                print(f"| {n} | {law} | {code} | {r['wall']:.1f} | {r['settle_ps'] / 1e6:.2f} | "
                      f"{r['dense_ps'] / 1e6:.2f} | {r['rss_kb'] / 1024:.1f} | {top} | {ratio[0]} | "
                      f"{ratio[1]} | {ratio[2]} |", flush=True)


if __name__ == "__main__":
    main()
