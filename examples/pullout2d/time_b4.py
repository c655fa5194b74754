#!/usr/bin/env python3
"""Case B4 of benchmarks/README.md: wall time of the L-shaped anchorage examples, one seed,
on 1 and 2 threads, run one after the other (run it on an otherwise idle machine).

    python3 examples/pullout2d/time_b4.py [--out runs/b4] [--examples L_sand L_silt ...]

Prints the table of benchmarks/README.md ("B4 pullout2d"): the whole process's wall time and
peak resident memory (GNU time), the steps, the speed and the stages from summary.json.
"""
import argparse
import json
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def time_one(example, threads, out):
    cmd = ["/usr/bin/time", "-v", str(ROOT / "build/geodem"), "run",
           str(ROOT / f"examples/pullout2d/{example}.toml"), "--out", str(out), "--overwrite",
           "--quiet", "--set", "seeds=1", "--threads", str(threads)]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=True)
    wall = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", proc.stderr)
    hours, minutes, seconds = (float(g) if g else 0.0 for g in wall.groups())
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr).group(1))
    summary = pathlib.Path(out) / "summary.json"
    if not summary.exists():  # a multi-seed layout keeps each run's summary under runs/
        summary = pathlib.Path(out) / "runs" / "seed1" / "summary.json"
    timing = json.loads(summary.read_text())["timing"]
    return {
        "wall": 3600 * hours + 60 * minutes + seconds,
        "rss_mb": rss_kb / 1024,
        "grains": timing["particles"],
        "steps": timing["steps"],
        "speed": timing["particle_steps_per_s"] / 1e6,
        "stages": timing["stages_s"],
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="runs/b4")
    parser.add_argument("--examples", nargs="+", default=["L_sand", "L_silt"])
    args = parser.parse_args()
    print("| case | threads | discs | steps | wall s | M disc-steps/s | contact forces s "
          "| integration s | neighbour search s | structures s | peak RSS |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for example in args.examples:
        for threads in (1, 2):
            r = time_one(example, threads, pathlib.Path(args.out) / f"{example}_t{threads}")
            st = r["stages"]
            print(f"| {example} | {threads} | {r['grains']:,} | {r['steps']:,} | {r['wall']:.1f} "
                  f"| {r['speed']:.1f} | {st['contact forces']:.1f} | {st['integration']:.1f} "
                  f"| {st['neighbour search']:.1f} | {st['structures']:.1f} "
                  f"| {r['rss_mb']:.0f} MB |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
