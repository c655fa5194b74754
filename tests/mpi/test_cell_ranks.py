#!/usr/bin/env python3
"""`mpirun -n K geodem run` of the lab tests in a periodic cell spreads one test over K ranks
with the same bits for any K (slabs along the cell's first fractional coordinate, closing in a
ring): the 2D triaxial test of bonded pair clumps (tests/mpi/triaxial2d.toml in a periodic
cell: radius growth with the cell servo, friction reduction, bonds, two compressions, VTK
frames in pieces) on 1, 2 and 4 ranks (oversubscribed), the 3D triaxial test of spheres on 1
and 2 ranks, and a simple shear test on 1 and 2 ranks write the same history.csv,
preparation.csv and results. Killed (SIGKILL after a checkpoint) on 2 ranks and resumed on 4,
or by one process without mpirun, the 2D test writes the files of the uninterrupted run. A
cell too narrow for the ranks once the compaction has grown the grains is refused with exit
code 2 before the run starts.

    test_cell_ranks.py PATH/TO/geodem
Exit 77 (skipped) without mpirun or without MPI in geodem.
"""
import os
import signal
import subprocess
import sys
import tempfile

from test_scene_ranks import check, failures, mpi_launch, pieces, stop_at_checkpoint
from test_triaxial_ranks import outputs

HERE = os.path.dirname(os.path.abspath(__file__))


def periodic(name, tmp, replace=(), prefix="cell_"):
    """tests/mpi/`name` in a periodic cell, written to `tmp` as `prefix`+`name`, with (old, new)
    replacements."""
    with open(os.path.join(HERE, name)) as f:
        text = f.read().replace("[sample]\n", '[sample]\nboundary = "periodic"\n', 1)
    for old, new in replace:
        text = text.replace(old, new)
    path = os.path.join(tmp, prefix + name)
    with open(path, "w") as f:
        f.write(text)
    return path


def main() -> int:
    geodem = sys.argv[1]
    launch = mpi_launch(geodem)
    if launch is None:
        return 77
    mpirun, env = launch

    def run(ranks, scenario, out, *extra):
        launcher = [mpirun, "-n", str(ranks)] if ranks else []
        args = launcher + [geodem, "run", scenario, "--out", out, "--quiet"] + list(extra)
        return subprocess.run(args, env=env, text=True, capture_output=True, timeout=600)

    with tempfile.TemporaryDirectory() as tmp:
        triaxial2d = periodic("triaxial2d.toml", tmp)
        triaxial3d = periodic("triaxial3d.toml", tmp)
        narrow = periodic("triaxial2d.toml", tmp, [("box = [0.8, 0.8]", "box = [0.4, 0.8]"),
                                                   ("count = 300", "count = 150")],
                          "narrow_")
        simple = os.path.join(tmp, "simple_shear.toml")
        with open(narrow) as f:
            text = f.read()
        with open(simple, "w") as f:
            f.write(text.replace('kind = "triaxial"', 'kind = "simple_shear"')
                    .split("[shear]")[0] + "[loading]\nnormal_stress = [1e5]\n"
                    "max_shear_strain = 0.01\n[output]\nplots = false\n")
        refs = {}
        for scenario, counts, grains in ((triaxial2d, (1, 2, 4), 600), (triaxial3d, (1, 2), 400),
                                         (simple, (1, 2), 300)):
            name = os.path.basename(scenario)
            for ranks in counts:
                out = os.path.join(tmp, f"{name}.{ranks}")
                r = run(ranks, scenario, out)
                if r.returncode != 0:
                    check(False, f"{name} on {ranks} ranks ran: {r.stdout}{r.stderr}")
                    continue
                got = outputs(out)
                if scenario == triaxial2d:
                    count, ids = pieces(out)
                    cells = [f for f in os.listdir(os.path.join(out, "vtk"))
                             if f.startswith("cell_")]
                    res = got["results"]
                    check(res["preparation"]["bonds"] > 0 and count == ranks and
                          sorted(ids) == list(range(grains)) and len(cells) >= 2 and
                          all(t["phi_peak_deg"] > 15.0 for t in res["tests"]),
                          f"{name} on {ranks} ranks: {res['preparation']['bonds']} bonds, peak "
                          f"friction {[round(t['phi_peak_deg'], 2) for t in res['tests']]} deg, "
                          f"the last frame in {count} pieces holding every member once, "
                          f"{len(cells)} cell outlines")
                if ranks == 1:
                    refs[name] = got
                    continue
                rows = len(got["history"]) - 1
                check(rows >= 10 and got == refs.get(name),
                      f"{name}: history ({rows} rows), preparation and results on {ranks} ranks "
                      f"the same as on 1 rank")

        # Killed on 2 ranks after a checkpoint, resumed on 4 and by one process.
        name = os.path.basename(triaxial2d)
        for then in (4, 0):
            out = os.path.join(tmp, f"killed.{then}")
            args = [mpirun, "-n", "2", geodem, "run", triaxial2d, "--out", out, "--quiet",
                    "--set", "checkpoint.every_steps=5000"]
            ck = stop_at_checkpoint(args, env, out, 40000, signal.SIGKILL)
            if ck is None:
                check(False, f"{name} on 2 ranks ended before it was killed")
                continue
            launcher = [mpirun, "-n", str(then)] if then else []
            r = subprocess.run(launcher + [geodem, "run", triaxial2d, "--resume", out, "--quiet",
                                           "--set", "checkpoint.every_steps=5000"],
                               env=env, text=True, capture_output=True, timeout=600)
            check(r.returncode == 0 and outputs(out) == refs.get(name),
                  f"{name}: SIGKILL on 2 ranks (checkpoints {ck[-1:]}), resumed on "
                  f"{then or 'one process without mpirun'}: the files of the uninterrupted run "
                  f"{'' if r.returncode == 0 else r.stderr}")

        r = run(4, narrow, os.path.join(tmp, "narrow.out"))
        words = [os.path.basename(narrow), "mpirun -n", "will grow", "too thin"]
        check(r.returncode == 2 and all(w in r.stderr for w in words) and
              r.stderr.count("error:") == 1,
              f"a cell too narrow for 4 ranks refused: exit {r.returncode}, {r.stderr.strip()}")
    print(f"{len(failures)} failures" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
