#!/usr/bin/env python3
"""Benchmark B1 triax3d: geodem and yade (2023.02a) side by side on the triaxial test of
yade's triax tutorial.

usage: run_b1.py [--n 1000] [--seeds 1 2 3] [--codes geodem yade] [--geodem build/geodem]
                 [--yade yade] [--out benchmarks/results/b1] [--reuse] [--table-only]

Each case runs on one thread (geodem --threads 1, yade -n -j1 -x) under /usr/bin/time -v,
one after the other, in OUT/N<n>_s<seed>/<code>/. Prints one markdown table per case (wall
time of the process, the code's own wall time, porosity after preparation, peak q, friction
angle at the peak, peak RSS) and, per N and code, the mean and standard deviation over the
seeds plus the ratio yade wall time / geodem wall time.

--reuse keeps a case whose result files are already there (e.g. a long yade run started
by hand with the same layout); --table-only runs nothing and tabulates what is there.
"""
import argparse
import json
import math
import re
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent


def time_v(cmd, log, cwd=None):
    """Runs cmd under /usr/bin/time -v, output to log; returns (wall s, peak RSS kB)."""
    with open(log, "w") as fh:
        r = subprocess.run(["/usr/bin/time", "-v", *cmd], cwd=cwd, stdout=fh, stderr=subprocess.STDOUT)
    text = Path(log).read_text(errors="replace")
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{text[-3000:]}")
    return parse_time_v(text)


def parse_time_v(text):
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", text)
    parts = [float(p) for p in m.group(1).split(":")]
    wall = sum(p * 60 ** k for k, p in enumerate(reversed(parts)))
    return wall, rss


def case_dir(out, n, seed, code):
    return Path(out) / f"N{n}_s{seed}" / code


def run_geodem(exe, n, seed, d, reuse, dry):
    log = d / "time.log"
    if not ((reuse or dry) and (d / "summary.json").exists() and log.exists()):
        if dry:
            return None
        d.mkdir(parents=True, exist_ok=True)
        time_v([str(exe), "run", str(HERE / "geodem_b1.toml"), "--out", str(d / "run"), "--overwrite", "--quiet",
                "--threads", "1", "--set", f"sample.count={n}", "--set", f"seed={seed}"], log)
        (d / "summary.json").write_text((d / "run" / "summary.json").read_text())
    wall, rss = parse_time_v(log.read_text(errors="replace"))
    s = json.loads((d / "summary.json").read_text())
    r, t = s["results"], s["timing"]
    return {"wall": wall, "own_wall": t["wall_s"], "rss_kb": rss, "steps": t["steps"],
            "porosity": r["preparation"]["porosity"], "porosity0": r["porosity_initial"],
            "peak_q": r["peak_q"], "eps_peak": r["axial_strain_at_peak"], "phi": r["phi_peak_deg"]}


def run_yade(exe, n, seed, d, reuse, dry):
    log = d / "time.log"
    res = d / "result.json"
    if not ((reuse or dry) and res.exists() and log.exists()):
        if dry:
            return None
        d.mkdir(parents=True, exist_ok=True)
        # yade writes small side files into its working folder: run it in the case folder
        time_v([exe, "-n", "-j1", "-x", str(HERE / "yade_triax.py"), str(n), str(seed), str(res)], log, cwd=d)
    wall, rss = parse_time_v(log.read_text(errors="replace"))
    r = json.loads(res.read_text())
    return {"wall": wall, "own_wall": r["wall_s"]["total"], "rss_kb": rss, "steps": r["steps"]["total"],
            "porosity": r["porosity_after_preparation"], "porosity0": r["porosity_initial"],
            "peak_q": r["peak_q"], "eps_peak": r["axial_strain_at_peak"], "phi": r["phi_peak_deg"]}


def mean_sd(xs):
    if not xs:
        return math.nan, math.nan
    return statistics.fmean(xs), (statistics.stdev(xs) if len(xs) > 1 else 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, nargs="+", default=[1000])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--codes", nargs="+", default=["geodem", "yade"], choices=["geodem", "yade"])
    ap.add_argument("--geodem", default=str(ROOT / "build" / "geodem"))
    ap.add_argument("--yade", default="yade")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "b1"))
    ap.add_argument("--reuse", action="store_true", help="keep cases already run in OUT")
    ap.add_argument("--table-only", action="store_true", help="run nothing, tabulate OUT")
    a = ap.parse_args()

    runners = {"geodem": lambda n, s, d: run_geodem(a.geodem, n, s, d, a.reuse, a.table_only),
               "yade": lambda n, s, d: run_yade(a.yade, n, s, d, a.reuse, a.table_only)}
    rows = []
    for n in a.n:
        for seed in a.seeds:
            for code in a.codes:
                r = runners[code](n, seed, case_dir(a.out, n, seed, code))
                if r is None:
                    continue
                r.update(n=n, seed=seed, code=code)
                rows.append(r)
                print(f"done: N={n} seed={seed} {code} {r['wall']:.1f} s", file=sys.stderr, flush=True)

    print("| N | seed | code | wall s | own wall s | steps | porosity after preparation | "
          "porosity at compression start | peak q (kPa) | axial strain at peak (%) | "
          "phi peak (deg) | peak RSS MB |")
    print("| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in rows:
        print(f"| {r['n']} | {r['seed']} | {r['code']} | {r['wall']:.1f} | {r['own_wall']:.1f} | "
              f"{r['steps']} | {r['porosity']:.4f} | {r['porosity0']:.4f} | {r['peak_q'] / 1e3:.2f} | "
              f"{100 * r['eps_peak']:.2f} | {r['phi']:.2f} | {r['rss_kb'] / 1024:.0f} |")

    print()
    print("| N | code | seeds | porosity | peak q (kPa) | phi peak (deg) | mean wall s | "
          "yade / geodem wall | yade / geodem own wall |")
    print("| ---: | --- | ---: | --- | --- | --- | ---: | ---: | ---: |")
    for n in a.n:
        walls = {}
        for code in a.codes:
            sel = [r for r in rows if r["n"] == n and r["code"] == code]
            if sel:
                walls[code] = (statistics.fmean(r["wall"] for r in sel), statistics.fmean(r["own_wall"] for r in sel))
        for code in a.codes:
            sel = [r for r in rows if r["n"] == n and r["code"] == code]
            if not sel:
                continue
            cells = []
            for key, scale, fmt in (("porosity", 1, "{:.4f} +- {:.4f}"), ("peak_q", 1e-3, "{:.2f} +- {:.2f}"),
                                    ("phi", 1, "{:.2f} +- {:.2f}")):
                m, sd = mean_sd([r[key] * scale for r in sel])
                cells.append(fmt.format(m, sd))
            ratio = ratio_own = ""
            if code == "yade" and "geodem" in walls and "yade" in walls:
                ratio = f"{walls['yade'][0] / walls['geodem'][0]:.2f}"
                ratio_own = f"{walls['yade'][1] / walls['geodem'][1]:.2f}"
            print(f"| {n} | {code} | {len(sel)} | {' | '.join(cells)} | {walls[code][0]:.1f} | {ratio} | {ratio_own} |")


if __name__ == "__main__":
    main()
