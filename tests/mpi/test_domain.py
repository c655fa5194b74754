#!/usr/bin/env python3
"""A decomposed domain gives the bits of one process: the pressed packing of the thread
determinism test (2D and 3D, frictional and with rolling springs and bonds) run by one process
and by 1, 2 and 4 MPI ranks (oversubscribed) ends with byte-identical grain states, after
grains have moved between ranks. With the ranks' grains in cell order (renumbered every 3
list builds, unlike the one-process reference) 1, 2 and 4 ranks agree with each other.

    test_domain.py PATH/TO/geodem_domain_run
Exit 77 (skipped) without mpirun.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile


def main() -> int:
    runner = sys.argv[1]
    mpirun = shutil.which("mpirun")
    if not mpirun:
        print("no mpirun: skipped")
        return 77
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1",
               # (more ranks than cores: a waiting rank gives its core to the others)
               OMPI_MCA_mpi_yield_when_idle="1")
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for dim, extras, steps in ((2, 0, 600), (2, 1, 600), (3, 0, 400), (3, 1, 400)):
            case = f"{dim}D {'bonds and rolling' if extras else 'frictional'}"
            ref = os.path.join(tmp, "serial.txt")
            subprocess.run([runner, str(dim), str(extras), str(steps), "serial", ref],
                           check=True, env=env)
            reference = open(ref).read()
            sorted_reference = None
            for mode, ranks in (("domain", 1), ("domain", 2), ("domain", 4), ("sorted", 1),
                                ("sorted", 2), ("sorted", 4)):
                out = os.path.join(tmp, f"{mode}{ranks}.txt")
                r = subprocess.run([mpirun, "-n", str(ranks), runner, str(dim), str(extras),
                                    str(steps), mode, out], env=env, text=True,
                                   capture_output=True, timeout=600)
                if r.returncode != 0:
                    print(f"{case}, {ranks} ranks: failed\n{r.stdout}{r.stderr}")
                    failures += 1
                    continue
                owned = [int(m) for m in re.findall(r"rank \d+: (\d+) grains", r.stdout)]
                ghosts = [int(m) for m in re.findall(r"\((\d+) ghosts\)", r.stdout)]
                result = open(out).read()
                if mode == "sorted":  # cell order: the 1-rank run is the reference
                    sorted_reference = sorted_reference or result
                    same = result == sorted_reference and result != reference
                else:
                    same = result == reference
                # Grains crossed between ranks: the counts left the equal split.
                moved = ranks == 1 or any(n != 12000 // ranks for n in owned)
                print(f"{case}, {mode}, {ranks} ranks: grains {owned}, ghosts {ghosts}: "
                      f"{'same bits' if same else 'DIFFERENT'}"
                      f"{'' if moved else ' (no grain changed rank: case too quiet)'}")
                failures += (not same) + (not moved) + (sum(owned) != 12000)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
