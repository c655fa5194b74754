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
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benchmarks" / "b2_settle3d"))
from run_b2 import time_v  # noqa: E402  (/usr/bin/time -v: wall seconds, peak RSS kB)


def time_one(example, threads, out):
    wall, rss_kb, _ = time_v([str(ROOT / "build/geodem"), "run",
                              str(ROOT / f"examples/pullout2d/{example}.toml"), "--out", str(out),
                              "--overwrite", "--quiet", "--set", "seeds=1", "--threads",
                              str(threads)])
    timing = json.loads((pathlib.Path(out) / "summary.json").read_text())["timing"]
    return {
        "wall": wall,
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
