#!/usr/bin/env python3
"""Benchmark B2 settle3d: geodem and (with --with-peers) LIGGGHTS 3.8 side by side.

usage: run_b2.py [--with-peers] [--n 20000 200000] [--dims 3 2] [--settle 50000]
                 [--dense 10000] [--out benchmarks/results/b2] [--geodem build/geodem]
                 [--liggghts-results FILE ...]

For each N: writes the common initial state, runs geodem (3D, and 2D discs with
--dims 2) and LIGGGHTS (3D) one after the other, each on one thread/process, and prints
one markdown table: case, N, code, wall seconds, particle-steps/s while settling and on
the settled bed (10,000 steps), peak RSS and bytes per grain, the bed height, and the
geodem/LIGGGHTS ratios. Peak memory comes from /usr/bin/time -v.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent


def time_v(cmd, cwd=None):
    """Runs cmd under /usr/bin/time -v; returns (wall seconds, peak RSS kB, output)."""
    r = subprocess.run(["/usr/bin/time", "-v", *cmd], cwd=cwd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr[-3000:]}")
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1))
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", r.stderr)
    parts = [float(p) for p in m.group(1).split(":")]
    wall = sum(p * 60 ** k for k, p in enumerate(reversed(parts)))
    return wall, rss, r.stdout + r.stderr


def run_geodem(exe, n, dim, out, settle, dense, threads=1):
    subprocess.run([sys.executable, str(HERE / "geodem_scenario.py"), str(n), str(out), "--dim", str(dim),
                    "--settle", str(settle), "--dense", str(dense)], check=True)
    return time_geodem(exe, out / f"settle{dim}d.toml", out / f"geodem{dim}d_t{threads}", n, dim, settle,
                       threads)


def time_geodem(exe, scenario, res, n, dim, settle, threads=1):
    """Runs a B2-style scenario (settle, then the dense bed) and reads its speeds per phase from
    history.csv's wall-clock column."""
    wall, rss, _ = time_v([str(exe), "run", str(scenario), "--out", str(res), "--overwrite", "--quiet",
                           "--threads", str(threads)])
    rows = list(csv.DictReader(open(res / "history.csv")))
    at = {int(r["step"]): r for r in rows}
    a = at[settle + 1]
    b = rows[-1]
    t_settle = float(a["wall_s"])
    t_dense = float(b["wall_s"]) - t_settle
    summary = json.loads((res / "summary.json").read_text())
    top = summary["results"]["centres_max"][dim - 1]
    return {"wall": wall, "settle_ps": n * settle / t_settle,
            "dense_ps": n * (int(b["step"]) - int(a["step"])) / t_dense, "rss_kb": rss, "top": top,
            "ke": float(b["kinetic_energy"])}


def run_liggghts(n, out, settle, dense):
    r = subprocess.run(["bash", str(HERE / "run_liggghts.sh"), str(n), str(out / "liggghts"), str(settle), str(dense)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"LIGGGHTS run failed:\n{r.stderr[-3000:]}")
    return parse_liggghts_line(r.stdout)


def parse_liggghts_line(line):
    """The key=value line that run_liggghts.sh prints, as a result row."""
    kv = dict(tok.split("=", 1) for tok in line.split() if "=" in tok)
    return {"wall": float(kv["wall_s"]), "settle_ps": float(kv["settle_pstep_per_s"]),
            "dense_ps": float(kv["dense_pstep_per_s"]), "rss_kb": int(kv["peak_rss_kb"]),
            "top": float(kv["final_zmax"]), "ke": float(kv["final_ke"])}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--with-peers", action="store_true", help="install and run LIGGGHTS too")
    ap.add_argument("--n", type=int, nargs="+", default=[20000])
    ap.add_argument("--dims", type=int, nargs="+", default=[3, 2])
    ap.add_argument("--settle", type=int, default=50000)
    ap.add_argument("--dense", type=int, default=10000)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "b2"))
    ap.add_argument("--geodem", default=str(ROOT / "build" / "geodem"))
    ap.add_argument("--threads", type=int, nargs="+", default=[1],
                    help="geodem runs once per thread count (ratios against the first)")
    ap.add_argument("--liggghts-results", nargs="+", default=[], metavar="FILE",
                    help="lines printed by run_liggghts.sh earlier on this machine (the run of the "
                         "same N is tabulated instead of running LIGGGHTS again)")
    a = ap.parse_args()
    earlier = {}
    for f in a.liggghts_results:
        for line in Path(f).read_text().splitlines():
            if line.startswith("n="):
                earlier[int(line.split()[0][2:])] = parse_liggghts_line(line)
    if a.with_peers:
        subprocess.run([str(ROOT / "scripts" / "install-deps.sh"), "--with-peers"], check=True)
    rows = []
    for n in a.n:
        out = Path(a.out) / f"n{n}"
        out.mkdir(parents=True, exist_ok=True)
        subprocess.run([sys.executable, str(HERE / "liggghts_input.py"), "-n", str(n), "-o", str(out),
                        "--settle-steps", str(a.settle), "--dense-steps", str(a.dense)],
                       check=True, capture_output=True)
        results = {}
        for dim in a.dims:
            for t in a.threads:
                code = f"geodem {dim}D" + (f" {t} threads" if t != 1 else "")
                results[code] = run_geodem(a.geodem, n, dim, out, a.settle, a.dense, t)
                results[code]["threads"] = t
                print(f"{code} N={n}: {results[code]}", file=sys.stderr)
        if n in earlier:
            results["LIGGGHTS 3D"] = earlier[n]
        elif a.with_peers:
            results["LIGGGHTS 3D"] = run_liggghts(n, out, a.settle, a.dense)
            print(f"LIGGGHTS N={n}: {results['LIGGGHTS 3D']}", file=sys.stderr)
        rows.append((n, results))

    print("| N | code | wall s | settle Mps/s | dense Mps/s | peak RSS MB | bytes/grain | bed top m | ratio settle | ratio dense | ratio memory | dense / 1 thread |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n, results in rows:
        peer = results.get("LIGGGHTS 3D")
        for code, r in results.items():
            ratio = ("", "", "")
            if peer and code == "geodem 3D":
                ratio = (f"{r['settle_ps'] / peer['settle_ps']:.2f}", f"{r['dense_ps'] / peer['dense_ps']:.2f}",
                         f"{r['rss_kb'] / peer['rss_kb']:.2f}")
            one = results.get(code.split(" threads")[0].rsplit(" ", 1)[0] if " threads" in code else code)
            speedup = f"{r['dense_ps'] / one['dense_ps']:.2f}" if one and r.get("threads", 1) != 1 else ""
            print(f"| {n} | {code} | {r['wall']:.1f} | {r['settle_ps'] / 1e6:.2f} | {r['dense_ps'] / 1e6:.2f} | "
                  f"{r['rss_kb'] / 1024:.1f} | {r['rss_kb'] * 1024 / n:.0f} | {r['top']:.4f} | "
                  f"{ratio[0]} | {ratio[1]} | {ratio[2]} | {speedup} |")


if __name__ == "__main__":
    main()
