#!/usr/bin/env python3
"""`mpirun -n K geodem run scene.toml` spreads one scene over K ranks with the same bits for any
K: a 3D settle (Hertz law with rolling resistance, VTK frames in pieces), a 2D biaxial test of
bonded discs and pair clumps (servo-controlled walls over two stages, bonds breaking and clumps
lying across rank boundaries), a pull-out of a sheet (a spar chain every rank holds whole,
its loads summed over the ranks), layers added by a stage (discs and clumps placed clear of the
whole domain's grains, each rank keeping its own) and the staged example (a wall removed, grains
excavated, a servo-loaded plate) on 1, 2 and 4 ranks (oversubscribed; the 2 ranks with 2
threads each) write the same history.csv (every column but the wall-clock time), the same
particles.csv and the same results in summary.json, the 4 ranks with their cuts moved to even
their work (`--rebalance 1`: they move in the layers' run and others). Killed (SIGTERM, or SIGKILL after periodic
checkpoints) and resumed on another number of ranks, or by one process without mpirun, they
write the history and grains of the uninterrupted run. An instability on one rank stops every
rank with one diagnosis.

    test_scene_ranks.py PATH/TO/geodem
Exit 77 (skipped) without mpirun or without MPI in geodem.
"""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
# Deposit on a gate, gate removed, excavation (grains removed), servo-loaded plate.
STAGED = os.path.join(HERE, "..", "..", "examples", "staged2d", "scenario.toml")
failures = []


def check(ok, what):
    print(("ok: " if ok else "FAILED: ") + what)
    if not ok:
        failures.append(what)


def history(path):
    """The rows of history.csv without the wall-clock column."""
    with open(path) as f:
        rows = list(csv.reader(f))
    keep = [k for k, name in enumerate(rows[0]) if name != "wall_s"]
    return [[r[k] for k in keep] for r in rows]


def pieces(out, ext=".pvtu"):
    """Grain ids of the last frame, read from the pieces its .pvtu lists (with ".pvtp": the
    contact pieces' line counts)."""
    vtk = os.path.join(out, "vtk")
    last = sorted(f for f in os.listdir(vtk) if f.endswith(ext))[-1]
    ids, count = [], 0
    for piece in ET.parse(os.path.join(vtk, last)).getroot().iter("Piece"):
        count += 1
        data = open(os.path.join(vtk, piece.get("Source")), "rb").read()
        head, blob = data.split(b"<AppendedData encoding=\"raw\">\n_", 1)
        root = ET.fromstring(head.decode() + "</VTKFile>")
        if ext == ".pvtp":
            ids.append(int(root.find(".//Piece").get("NumberOfLines")))
            continue
        n = int(root.find(".//Piece").get("NumberOfPoints"))
        for arr in root.iter("DataArray"):
            if arr.get("Name") == "id":
                at = int(arr.get("offset"))
                size = int.from_bytes(blob[at:at + 8], "little")
                assert size == 4 * n
                ids += [int.from_bytes(blob[at + 8 + 4 * k:at + 12 + 4 * k], "little")
                        for k in range(n)]
    return count, ids


def signal_run(out, sig):
    """Sends `sig` to the ranks and mpirun of the run writing to `out` (the processes whose
    command line names that folder)."""
    for pid in os.listdir("/proc"):
        try:
            if pid.isdigit() and out.encode() in open(f"/proc/{pid}/cmdline", "rb").read():
                os.kill(int(pid), sig)
        except OSError:
            pass


def stop_at_checkpoint(args, env, out, at, sig):
    """Starts the run `args` (writing to `out`), sends it `sig` once its checkpoint of step `at`
    or later is written, and waits for it: the checkpoint files then, or None when the run ended
    first."""
    p = subprocess.Popen(args, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ckdir = os.path.join(out, "checkpoint")

    def newest():  # the step of the newest checkpoint written
        names = os.listdir(ckdir) if os.path.isdir(ckdir) else []
        return max([int(n[11:23]) for n in names if n.endswith(".bin")], default=0)
    while p.poll() is None and newest() < at:
        time.sleep(0.005)
    if p.poll() is not None:
        return None
    signal_run(out, sig)
    p.wait()
    return sorted(os.listdir(ckdir))


def mpi_launch(geodem):
    """mpirun and its environment for oversubscribed ranks (as root too); None without mpirun
    or without MPI in geodem."""
    mpirun = shutil.which("mpirun")
    version = subprocess.run([geodem, "--version"], capture_output=True, text=True).stdout
    if not mpirun or "MPI" not in version:
        print("no mpirun or geodem without MPI: skipped")
        return None
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1",
               # (more ranks than cores: a waiting rank gives its core to the others)
               OMPI_MCA_mpi_yield_when_idle="1")
    return mpirun, env


def main() -> int:
    geodem = sys.argv[1]
    launch = mpi_launch(geodem)
    if launch is None:
        return 77
    mpirun, env = launch

    def run(ranks, scenario, out, *sets, threads=1, extra=()):
        args = [mpirun, "-n", str(ranks), geodem, "run", os.path.join(HERE, scenario), "--out",
                out, "--quiet", "--threads", str(threads), *extra]
        for s in sets:
            args += ["--set", s]
        return subprocess.run(args, env=env, text=True, capture_output=True, timeout=600)

    with tempfile.TemporaryDirectory() as tmp:
        moves = {}  # the cuts' moves of the 4-rank runs, which weigh their work at every build
        for scenario in ("settle3d.toml", "biaxial2d.toml", "pullout2d.toml", "layers2d.toml",
                         STAGED):
            ref = None
            for ranks in (1, 2, 4):
                out = os.path.join(tmp, f"{os.path.basename(scenario)}.{ranks}")
                r = run(ranks, scenario, out, "output.plots=false", threads=2 if ranks == 2 else 1,
                        extra=["--rebalance", "1"] if ranks == 4 else [])
                if r.returncode != 0:
                    check(False, f"{scenario} on {ranks} ranks ran: {r.stdout}{r.stderr}")
                    continue
                got = {
                    "history": history(os.path.join(out, "history.csv")),
                    "particles": open(os.path.join(out, "particles.csv")).read(),
                    "results": json.load(open(os.path.join(out, "summary.json")))["results"],
                }
                res = got["results"]
                check(len(got["history"]) > 10 and res["status"] == "completed",
                      f"{scenario} on {ranks} ranks: {len(got['history']) - 1} history rows, "
                      f"{res['steps']} steps")
                if scenario == "settle3d.toml":
                    count, ids = pieces(out)
                    check(count == ranks and sorted(ids) == list(range(1000)),
                          f"{scenario} on {ranks} ranks: the last frame has {count} pieces "
                          f"holding grains 0-999 once each")
                    # The frame is drawn after the step's motion, the history counts the
                    # contacts of its force stage: a contact may open or close in between.
                    count, lines = pieces(out, ".pvtp")
                    contacts = int(float(got["history"][-1][got["history"][0].index("contacts")]))
                    got["contact lines"] = sum(lines)
                    check(count == ranks and abs(sum(lines) - contacts) <= 0.01 * contacts,
                          f"{scenario} on {ranks} ranks: the last contact frame's {count} pieces "
                          f"draw {sum(lines)} contacts, the history's last row counts {contacts}")
                    check(res["stop_reason"].startswith("at rest"),
                          f"{scenario} on {ranks} ranks stopped: {res['stop_reason']}")
                elif scenario == "pullout2d.toml":
                    sheet = res["chains"]["sheet"]
                    check([st["stop_reason"] for st in res["stages"]] == ["end of duration"] * 2
                          and sheet["tension_last"] > 500.0,
                          f"{scenario} on {ranks} ranks: pulled with "
                          f"{sheet['tension_last']:.0f} N/m at the end")
                elif scenario == "layers2d.toml":
                    check(res["particles"] == 660 and res["clumps"] == 30 and
                          res["bonds_created"] - res["bonds_broken"] > 0,
                          f"{scenario} on {ranks} ranks: {res['particles']} grains, "
                          f"{res['clumps']} clumps after the layer, "
                          f"{res['bonds_created'] - res['bonds_broken']} bonds intact")
                elif scenario == STAGED:
                    check([st["stop_reason"][:7] for st in res["stages"]] == ["at rest"] * 4 and
                          res["particles"] < 1500,
                          f"{scenario} on {ranks} ranks: 4 stages at rest, {res['particles']} "
                          f"grains left after the excavation")
                else:
                    check(0 < res["bonds_broken"] < res["bonds_created"] and
                          res["clumps"] == 100 and res["particles"] == 760,
                          f"{scenario} on {ranks} ranks: {res['bonds_broken']} of "
                          f"{res['bonds_created']} bonds broke, {res['clumps']} clumps")
                if ranks == 4:
                    timing = json.load(open(os.path.join(out, "summary.json")))["timing"]
                    moves[scenario] = timing["rebalance_moves"]
                    check(timing["ranks"] == 4, f"{scenario}: the summary names 4 ranks")
                if ref is None:
                    ref = got
                    continue
                for part in got:
                    check(got[part] == ref[part],
                          f"{scenario}: {part} on {ranks} ranks the same as on 1 rank")

        # A layer added on top leaves the ranks' work uneven, and so does settling: the cuts
        # moved (the modelled work decides, so the same runs move them alike each time), and
        # the results above are those of 1 rank all the same.
        check(moves.get("layers2d.toml", 0) > 0 and sum(m > 0 for m in moves.values()) >= 3,
              f"the cuts of the 4-rank runs moved (work weighed at every build): {moves}")

        # An instability on one rank stops all of them, with one diagnosis from rank 0.
        out = os.path.join(tmp, "unstable")
        r = run(2, "settle3d.toml", out, "time.step=0.002")
        summary = json.load(open(os.path.join(out, "summary.json")))["results"]
        check(r.returncode == 3 and r.stderr.count("unstable:") == 1 and
              summary["status"] == "unstable" and "overlap" in summary["stop_reason"],
              f"an overlap on 2 ranks: exit {r.returncode}, status {summary['status']}")
        # Killed, then resumed on another number of ranks: the history and the final grains of
        # the uninterrupted runs above (checkpoints do not change the bits). SIGTERM stops every
        # rank at a step they agree on, with a checkpoint; SIGKILL leaves the last periodic one
        # (and history rows after it, which the resumed run drops).
        for scenario, first, then, sig, at in (("settle3d.toml", 2, 4, signal.SIGTERM, 3000),
                                               ("biaxial2d.toml", 4, 0, signal.SIGKILL, 6000),
                                               ("pullout2d.toml", 2, 4, signal.SIGKILL, 20000),
                                               ("layers2d.toml", 4, 2, signal.SIGKILL, 6000)):
            out = os.path.join(tmp, f"{scenario}.killed")
            args = [mpirun, "-n", str(first), geodem, "run", os.path.join(HERE, scenario),
                    "--out", out, "--quiet", "--set", "checkpoint.every_steps=1000"]
            hist = os.path.join(out, "history.csv")
            ck = stop_at_checkpoint(args, env, out, at, sig)  # killed some thousand steps in
            if ck is None:
                check(False, f"{scenario} on {first} ranks ended before it was killed")
                continue
            # (then = 0: one process without mpirun goes on as a domain of one rank)
            launcher = [mpirun, "-n", str(then)] if then else []
            r = subprocess.run(launcher + [geodem, "run", os.path.join(HERE, scenario),
                                           "--resume", out, "--quiet", "--set",
                                           "checkpoint.every_steps=1000"], env=env, text=True,
                               capture_output=True, timeout=600)
            ref = os.path.join(tmp, f"{scenario}.1")
            same = r.returncode == 0 and \
                history(hist) == history(os.path.join(ref, "history.csv")) and \
                open(os.path.join(out, "particles.csv")).read() == \
                open(os.path.join(ref, "particles.csv")).read()
            check(same, f"{scenario}: {sig.name} on {first} ranks (checkpoints {ck[-1:]}), "
                        f"resumed on {then or 'one process without mpirun'}: history and "
                        f"grains of the uninterrupted run "
                        f"{'' if r.returncode == 0 else r.stderr}")
    print(f"{len(failures)} failures" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
