#!/usr/bin/env python3
"""Crash harness: every kind of run killed with SIGKILL at random moments, resumed, and
compared with a run that was never interrupted.

For each kind a small scenario is run once to the end (the reference, and its duration T).
Then the same scenario is started into fresh folders, each SIGKILLed after a random
fraction of T, until `--kills` runs were killed (a run that ends before its kill is
checked too, not counted) (so kills land in every stage, in output writes and in checkpoint
writes: checkpoints are written every few hundred steps); a third of the runs is killed a
second time while resuming. The folder is then finished the way a user would: `--resume`
when it holds a checkpoint (a study: when it has begun its runs; it keeps the finished ones
and continues the others), the same command with `--overwrite` otherwise (killed before
its first checkpoint). Every CSV and VTK file and
the summary's results must equal the reference's, bit for bit (a scene's wall_s column
aside).

    tests/crash/crash_harness.py GEODEM [--kills 20] [--kinds scene,triaxial,...] [--seed 1]

Prints a table (docs/verification.md, "Crash consistency") and exits 1 on any difference.
"""
import argparse
import csv
import hashlib
import io
import json
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "cli"))
from small_scenarios import (BASE, CHECKPOINT_SCENE, LAB_CHECKPOINT_TRIAXIAL,  # noqa: E402
                             SMALL_PULLOUT, SMALL_STAGED, shear)

CHECKPOINT = "\n[checkpoint]\nevery_steps = {every}\nkeep = 2\n"

SCENE = CHECKPOINT_SCENE.split("[checkpoint]")[0]  # the harness sets its own period
TRIAXIAL = LAB_CHECKPOINT_TRIAXIAL
# An L anchor with a free front face under a surcharge plate: every stage of the kind.
PULLOUT = (SMALL_PULLOUT.format(shape="L", trench="trench_depth = 0.05")
           .replace('front = "wall"', 'front = "free"')
           .replace("[pull]", "[surcharge]\npressure = 2000.0\n[pull]")
           .replace("max_displacement = 0.03", "max_displacement = 0.01")
           + "[output]\nplots = false\n")
# The element tests on the same sample: the oedometer's steps between walls, and cycles in the
# periodic cell (every turning point and loop of the program's state crosses a checkpoint).
LAB_SAMPLE = TRIAXIAL.split("[shear]")[0]
OEDOMETER = (LAB_SAMPLE.replace('kind = "triaxial"', 'kind = "oedometer"')
             + "[loading]\nstresses = [2e5, 1e5]\n[output]\nplots = false\n")
CYCLIC = (LAB_SAMPLE.replace('kind = "triaxial"', 'kind = "cyclic_triaxial"')
          .replace("count = 150", 'count = 150\nboundary = "periodic"')
          + "[loading]\namplitudes = [1e-4, 1e-3]\ncycles = 1\nsteps_per_cycle = 400\n"
          "[output]\nplots = false\n")
DIRECT_SHEAR = (LAB_SAMPLE.replace('kind = "triaxial"', 'kind = "direct_shear"')
                .replace("box = [0.4, 0.8]", "box = [0.8, 0.4]")
                + "[loading]\nnormal_stress = [1e5]\nmax_displacement = 0.004\n"
                "[output]\nplots = false\n")
SHEAR = shear(base="soil").replace("vtk = false", "vtk = false\nplots = false")
SERIES = ('kind = "series"\n' + BASE.replace("max_axial_strain = 0.04", "max_axial_strain = 0.02")
          + "[series]\ncounts = [60, 120]\nseeds = 2\ntolerance = 0.05\n")
PULLOUT_SEEDS = PULLOUT.replace("seed = 1", "seed = 1\nseeds = 2").replace(
    "max_displacement = 0.01", "max_displacement = 0.004")

# kind: (scenario, checkpoint period in steps (None: none), a study)
CASES = {
    "scene": (SCENE, 300, False),
    "staged": (SMALL_STAGED, 1500, False),
    "triaxial": (TRIAXIAL, 2500, False),
    "triaxial_periodic": (TRIAXIAL.replace("count = 150", 'count = 150\nboundary = "periodic"'),
                          2500, False),
    "oedometer": (OEDOMETER, 2500, False),
    "cyclic_triaxial": (CYCLIC, 2500, False),
    "direct_shear": (DIRECT_SHEAR, 2500, False),
    "pullout": (PULLOUT, 3000, False),
    "interface_shear": (SHEAR, None, False),
    "series": (SERIES, 3000, True),
    "pullout_seeds": (PULLOUT_SEEDS, 4000, True),
}


def without_wall_time(x):
    """A summary's results less the wall-clock times of its runs (wall_s)."""
    if isinstance(x, dict):
        return {k: without_wall_time(v) for k, v in x.items() if k != "wall_s"}
    if isinstance(x, list):
        return [without_wall_time(v) for v in x]
    return x


def digests(folder):
    """SHA-256 of every CSV and VTK file under a run's folder (a scene's wall_s column
    left out) and its summary's results, by relative path."""
    folder = Path(folder)
    out = {}
    for p in sorted(folder.rglob("*")):
        if not p.is_file() or "checkpoint" in p.parts:
            continue
        if p.suffix in (".vtu", ".vtp", ".pvd"):
            out[str(p.relative_to(folder))] = hashlib.sha256(p.read_bytes()).hexdigest()
        elif p.suffix == ".csv":
            rows = list(csv.reader(io.StringIO(p.read_text())))
            if rows and "wall_s" in rows[0]:
                k = rows[0].index("wall_s")
                rows = [r[:k] + r[k + 1:] for r in rows]
            out[str(p.relative_to(folder))] = hashlib.sha256(repr(rows).encode()).hexdigest()
        elif p.name == "summary.json":
            s = json.loads(p.read_text())
            res = without_wall_time(s.get("results", {}))
            res.pop("checkpoint", None)
            out[str(p.relative_to(folder))] = json.dumps([s.get("status"), res], sort_keys=True)
    return out


class Harness:
    def __init__(self, geodem, work, rng, keep_failed=False):
        self.geodem, self.work, self.rng = geodem, Path(work), rng
        self.keep_failed = keep_failed

    def command(self, scenario, out, resume=False):
        cmd = [self.geodem, "run", str(scenario), "--quiet"]
        return cmd + (["--resume", str(out)] if resume else ["--out", str(out)])

    def run_killed(self, cmd, after):
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        try:
            p.wait(timeout=after)
            return False  # it finished before the kill
        except subprocess.TimeoutExpired:
            p.send_signal(signal.SIGKILL)
            p.wait()
            return True

    def finish(self, scenario, out, restartable):
        """Completes a killed folder as a user would; returns how."""
        has_checkpoint = any((out / "checkpoint").glob("checkpoint_*.bin"))
        if (restartable and (out / "runs").is_dir()) or has_checkpoint:
            how, cmd = "resumed", self.command(scenario, out, resume=True)
        else:  # killed before anything to resume from: the same run again
            how, cmd = "rerun", self.command(scenario, out) + ["--overwrite"]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
        if r.returncode != 0:
            raise RuntimeError(f"{how}: exit {r.returncode}: {r.stderr.strip()[-400:]}")
        return how

    def kind(self, name, kills):
        text, every, study = CASES[name]
        folder = self.work / name
        folder.mkdir(parents=True)
        scenario = folder / "scenario.toml"
        scenario.write_text(text + (CHECKPOINT.format(every=every) if every else ""))
        ref = folder / "ref"
        t0 = time.monotonic()
        r = subprocess.run(self.command(scenario, ref), capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"{name} reference: {r.stderr}")
        duration = time.monotonic() - t0
        expected = digests(ref)
        row = {"kind": name, "reference_s": duration, "kills": 0, "double": 0, "resumed": 0,
               "rerun": 0, "identical": 0, "runs": 0, "failures": []}
        k = 0
        while row["kills"] < kills and k < 3 * kills:  # kills that came after the end
            k += 1                                      # are not counted
            out = folder / f"kill{k}"
            at = self.rng.uniform(0.03, 0.97) * duration
            killed = self.run_killed(self.command(scenario, out), at)
            row["kills"] += killed
            if killed and self.rng.random() < 1 / 3 and (
                    any((out / "checkpoint").glob("checkpoint_*.bin")) or
                    (study and (out / "runs").is_dir())):
                again = self.rng.uniform(0.1, 0.6) * duration
                row["double"] += self.run_killed(self.command(scenario, out, resume=True), again)
            row["runs"] += 1
            try:
                how = self.finish(scenario, out, study) if killed else "finished"
                row[how] = row.get(how, 0) + 1
                got = digests(out)
                diff = sorted(n for n in set(got) | set(expected) if got.get(n) != expected.get(n))
                if diff:
                    row["failures"].append(f"kill {k} at {at:.2f} s: differs in {diff[:4]}")
                else:
                    row["identical"] += 1
            except Exception as e:  # noqa: BLE001 - every failure is reported in the table
                row["failures"].append(f"kill {k} at {at:.2f} s: {e}")
            if not self.keep_failed or not row["failures"]:
                shutil.rmtree(out, ignore_errors=True)
        return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("geodem")
    ap.add_argument("--kills", type=int, default=20)
    ap.add_argument("--kinds", default=",".join(CASES))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", help="work folder to keep (default: a temporary one)")
    a = ap.parse_args()
    work = Path(a.keep) if a.keep else Path(tempfile.mkdtemp(prefix="geodem_crash_"))
    h = Harness(str(Path(a.geodem).resolve()), work, random.Random(a.seed), bool(a.keep))
    print("| kind | reference run (s) | runs | killed | killed twice | resumed | rerun |"
          " identical to the reference |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    failures = []
    for name in a.kinds.split(","):
        row = h.kind(name, a.kills)
        print(f"| {name} | {row['reference_s']:.1f} | {row['runs']} | {row['kills']} |"
              f" {row['double']} | {row['resumed']} | {row['rerun']} |"
              f" {row['identical']} of {row['runs']} |", flush=True)
        failures += [f"{name}: {f}" for f in row["failures"]]
    for f in failures:
        print("FAILED", f)
    if not a.keep:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
