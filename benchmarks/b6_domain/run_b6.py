#!/usr/bin/env python3
"""B6: one model over MPI ranks (benchmarks/README.md, docs/parallel.md).

Settles a bed of N spheres with B2's grains and contacts (b2_settle3d/dense_bed_200k.toml,
scaled to N in a box of the same depth), checkpointed at its end; then times STEPS steps of
that dense bed on one process and decomposed over 1, 2 and 4 ranks
(geodem_domain_bench), one run after the other. Prints each rank's grains, ghosts, ghost
update bytes, message time and resident memory, and the whole run's rate.

usage: run_b6.py [--n 20000 200000] [--steps 2000] [--ranks 1 2 4] [--threads 1] [--rebalance B]
                 [--work DIR] [--build DIR]

--threads T: T threads in the one process and in each rank (ranks x threads should not exceed
the cores).
"""
import argparse
import math
import os
import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
BED = HERE.parent / "b2_settle3d" / "dense_bed_200k.toml"


def bed_scenario(n):
    """B2's settled-bed scenario for n spheres: the box side scales with sqrt(n)."""
    side = 3.6 * math.sqrt(n / 200000)
    text = BED.read_text().replace("count = 200000", f"count = {n}")
    text = re.sub(r"3\.6\b", f"{side:.6g}", text)
    return text


def dense_scenario(bed_text, bed_dir, steps):
    """The same scenario started from the bed's checkpoint: its walls and grains come from
    there (no [[walls]], [[clouds]] or [checkpoint] tables)."""
    blocks = re.split(r"(?m)^(?=\[)", bed_text)
    keep = [b for b in blocks if not b.startswith(("[[walls]]", "[[clouds]]", "[checkpoint]"))]
    text = re.sub(r"steps = \d+", f"steps = {steps}", "".join(keep))
    return text + f'[start]\ncheckpoint = "{bed_dir}"\n'


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, nargs="+", default=[20000, 200000])
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4])
    ap.add_argument("--threads", type=int, default=1, help="threads of each process")
    ap.add_argument("--rebalance", type=int, default=-1,
                    help="measure the work every this many list builds and move the cuts when "
                         "it stays uneven (0: never; default: the domain's, every 10)")
    ap.add_argument("--work", default=str(HERE.parent / "results" / "b6"))
    ap.add_argument("--build", default=str(HERE.parent.parent / "build"))
    a = ap.parse_args(argv[1:])
    build = Path(a.build)
    geodem, bench = build / "geodem", build / "benchmarks" / "b6_domain" / "geodem_domain_bench"
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1",
               GEODEM_THREADS=str(a.threads))
    for n in a.n:
        work = Path(a.work) / f"n{n}"
        work.mkdir(parents=True, exist_ok=True)
        bed_text = bed_scenario(n)
        (work / "bed.toml").write_text(bed_text)
        if not (work / "bed" / "summary.json").exists():
            subprocess.run([str(geodem), "run", str(work / "bed.toml"), "--out", str(work / "bed"),
                            "--overwrite", "--threads", "2", "--quiet"], check=True, env=env)
        dense = work / "dense.toml"
        dense.write_text(dense_scenario(bed_text, "bed", a.steps))
        print(f"== N = {n}, {a.steps} steps of the settled bed", flush=True)
        subprocess.run([str(bench), str(dense), str(a.steps), "serial"], check=True, env=env)
        for k in a.ranks:
            subprocess.run(["mpirun", "-n", str(k), "--bind-to", "none", str(bench), str(dense),
                            str(a.steps), "domain", str(a.rebalance)], check=True, env=env)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
