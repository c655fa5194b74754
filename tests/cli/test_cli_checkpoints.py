"""Runs stopped and resumed through the command line: stopped by SIGKILL or SIGTERM at
random points, or resumed from a checkpoint in any stage of a lab test or a pull-out, they
end as one that never stopped, bit for bit; a damaged newest checkpoint falls back to the
previous one; a changed scenario is refused.

Run by CTest: python3 test_cli_checkpoints.py GEODEM_BINARY REPO_ROOT
"""
import csv
import hashlib
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

import cli_case
from cli_case import run
from small_scenarios import CHECKPOINT_SCENE, LAB_CHECKPOINT_TRIAXIAL, SMALL_PULLOUT

GEODEM = None


def history_without_wall_time(folder):
    with open(Path(folder) / "history.csv") as f:
        rows = list(csv.reader(f))
    wall = rows[0].index("wall_s")
    return [r[:wall] + r[wall + 1:] for r in rows]


def folder_files(folder):
    """Bytes of every VTK file and the .pvd index, by name."""
    return {p.name: p.read_bytes() for p in sorted((Path(folder) / "vtk").iterdir())}


class CheckpointTest(unittest.TestCase):
    """Runs stopped by SIGKILL or SIGTERM at random points and resumed end as one that
    never stopped: same history (but its wall-clock column), same VTK files, same results."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)
        self.scenario = self.dir / "s.toml"
        self.scenario.write_text(CHECKPOINT_SCENE)
        self.ref = self.dir / "ref"
        t0 = time.monotonic()
        r = run("run", str(self.scenario), "--out", str(self.ref), "--quiet")
        self.ref_seconds = time.monotonic() - t0
        self.assertEqual(r.returncode, 0, r.stderr)

    def tearDown(self):
        self.tmp.cleanup()

    def stop_and_resume(self, sig, stops, seed):
        out = self.dir / f"run_{sig}"
        rng = random.Random(seed)
        fresh = [GEODEM, "run", str(self.scenario), "--out", str(out), "--quiet"]
        resume = [GEODEM, "run", str(self.scenario), "--resume", str(out), "--quiet"]
        stopped, launches = 0, 0
        while True:
            launches += 1
            self.assertLess(launches, 40, "the run never finished")
            has_checkpoint = (out / "checkpoint").is_dir() and any(
                p.suffix == ".bin" for p in (out / "checkpoint").iterdir())
            p = subprocess.Popen(resume if has_checkpoint else fresh, stderr=subprocess.PIPE,
                                 text=True)
            try:
                if stopped >= stops:
                    raise subprocess.TimeoutExpired(p.args, 0)
                p.wait(timeout=rng.uniform(0.2, 0.6) * self.ref_seconds)
            except subprocess.TimeoutExpired:
                if stopped < stops:
                    p.send_signal(sig)
                    err = p.communicate(timeout=120)[1]
                    if p.returncode == 0:  # it ended before the signal arrived
                        break
                    stopped += 1
                    if sig == signal.SIGTERM:
                        # A clean stop: exit 128 + 15, a checkpoint, outputs, the way to resume.
                        self.assertEqual(p.returncode, 143, err)
                        self.assertIn("--resume", err)
                        s = json.loads((out / "summary.json").read_text())
                        self.assertEqual(s["status"], "interrupted")
                        self.assertTrue(Path(s["results"]["checkpoint"]).is_file())
                    else:
                        self.assertEqual(p.returncode, -signal.SIGKILL, err)
                    continue
                err = p.communicate(timeout=300)[1]
            self.assertEqual(p.returncode, 0, err)
            break
        self.assertGreater(stopped, 0)
        self.assertEqual(history_without_wall_time(self.ref), history_without_wall_time(out))
        self.assertEqual(folder_files(self.ref), folder_files(out))
        a = json.loads((self.ref / "summary.json").read_text())["results"]
        b = json.loads((out / "summary.json").read_text())["results"]
        a.pop("checkpoint"), b.pop("checkpoint")
        self.assertEqual(a, b)

    def test_sigkill_at_random_points_then_resume_is_bitwise(self):
        self.stop_and_resume(signal.SIGKILL, stops=3, seed=1)

    def test_sigterm_checkpoints_and_resume_is_bitwise(self):
        self.stop_and_resume(signal.SIGTERM, stops=3, seed=2)

    def test_damaged_newest_checkpoint_falls_back_to_the_previous(self):
        out = self.dir / "damaged"
        shutil.copytree(self.ref, out)
        files = sorted((out / "checkpoint").glob("checkpoint_*.bin"))
        self.assertEqual(len(files), 2)  # keep = 2: the last periodic one and the final one
        newest = files[-1]
        data = bytearray(newest.read_bytes())
        data[len(data) // 2] ^= 0xFF
        newest.write_bytes(bytes(data))
        r = run("run", str(self.scenario), "--resume", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("checksum", r.stderr)
        self.assertIn(files[0].name, r.stderr)  # resumed from the previous one
        self.assertEqual(history_without_wall_time(self.ref), history_without_wall_time(out))
        # The damaged file was discarded; the resumed run wrote its own final checkpoint.
        self.assertEqual(sorted(p.name for p in (out / "checkpoint").glob("checkpoint_*.bin")),
                         [f.name for f in files])
        self.assertNotEqual(newest.read_bytes(), bytes(data))
        # Cut short, then nothing valid at all: a clear refusal.
        files[0].write_bytes(files[0].read_bytes()[:100])
        for f in (out / "checkpoint").glob("checkpoint_*.bin"):
            if f != files[0]:
                f.unlink()
        r = run("run", str(self.scenario), "--resume", str(out), "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("no valid checkpoint", r.stderr)
        self.assertIn("truncated", r.stderr)

    def test_resume_refuses_a_changed_scenario(self):
        r = run("run", str(self.scenario), "--resume", str(self.ref), "--quiet",
                "--set", "materials.0.friction=0.4")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("materials.0.friction", r.stderr)
        # The run's length may change: a finished run is extended from its final checkpoint.
        r = run("run", str(self.scenario), "--resume", str(self.ref), "--quiet",
                "--set", "time.duration=0.32")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((self.ref / "summary.json").read_text())
        self.assertAlmostEqual(s["results"]["time"], 0.32, delta=1e-3)


def output_digests(folder):
    """SHA-256 of every CSV and VTK file of a run's folder, and its summary's results."""
    folder = Path(folder)
    out = {}
    for p in sorted(folder.rglob("*")):
        if p.is_file() and p.suffix in (".csv", ".vtu", ".vtp", ".pvd"):
            out[str(p.relative_to(folder))] = hashlib.sha256(p.read_bytes()).hexdigest()
    results = json.loads((folder / "summary.json").read_text())["results"]
    results.pop("checkpoint", None)
    out["summary results"] = json.dumps(results, sort_keys=True)
    return out


class LabCheckpointTest(unittest.TestCase):
    """Lab tests resumed from a checkpoint in any of their stages end as one that never
    stopped: the same CSV files, VTK files and results, bit for bit."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def reference(self, text, every_steps):
        scenario = self.dir / "s.toml"
        scenario.write_text(text + f"\n[checkpoint]\nevery_steps = {every_steps}\nkeep = 1000\n")
        ref = self.dir / "ref"
        t0 = time.monotonic()
        r = run("run", str(scenario), "--out", str(ref), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        return scenario, ref, time.monotonic() - t0

    def resume_from_checkpoints(self, scenario, ref, at_least, steps=None):
        """Resumes a copy of the finished reference from each of its checkpoints (or from
        the first one at or after each of `steps`, and the last), as if the run had been
        killed after it: later checkpoints removed, later rows and frames still in the copy
        (the resumed run must trim them)."""
        expected = output_digests(ref)
        checkpoints = sorted((ref / "checkpoint").glob("checkpoint_*.bin"))
        self.assertGreaterEqual(len(checkpoints), at_least)
        if steps is not None:
            step_of = {cp: int(cp.stem.split("_")[1]) for cp in checkpoints}
            chosen = {checkpoints[-1]}
            for target in steps:
                after = [cp for cp in checkpoints if step_of[cp] >= target]
                if after:
                    chosen.add(after[0])
            checkpoints = sorted(chosen)
        for cp in checkpoints:
            out = self.dir / ("from_" + cp.stem)
            shutil.copytree(ref, out)
            for later in (out / "checkpoint").glob("checkpoint_*.bin"):
                if later.name > cp.name:
                    later.unlink()
            r = run("run", str(scenario), "--resume", str(out), "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn(cp.name, r.stderr)
            got = output_digests(out)
            self.assertEqual(sorted(got), sorted(expected), cp.name)
            for name in expected:
                self.assertEqual(got[name], expected[name], f"resumed from {cp.name}: {name}")
            shutil.rmtree(out)
        return expected

    def test_triaxial_resumes_from_every_stage_bitwise(self):
        scenario, ref, seconds = self.reference(LAB_CHECKPOINT_TRIAXIAL, 2500)
        prep = json.loads((ref / "summary.json").read_text())["results"]["preparation"]
        self.assertGreater(prep["bonds"], 0)
        with open(ref / "preparation.csv") as f:
            phases = {row["phase"] for row in csv.DictReader(f)}
        self.assertEqual(phases, {"1", "2", "3"})  # compaction, friction reduction, stabilisation
        # Checkpoints are numbered by the run's steps, which go on growing when each test
        # restarts from the prepared sample (and its step count).
        summary = json.loads((ref / "summary.json").read_text())
        res, total = summary["results"], summary["timing"]["steps"]
        names = sorted(p.name for p in (ref / "checkpoint").glob("checkpoint_*.bin"))
        self.assertEqual(names, [f"checkpoint_{k:012d}.bin" for k in range(2500, total + 1, 2500)])
        # From the first checkpoint in each stage (and near its middle): compaction,
        # friction reduction, stabilisation, then each test's consolidation and compression.
        prep_steps = res["preparation"]["steps"]
        offset = {"0": 0, "1": res["tests"][0]["steps"] - prep_steps}  # run steps - world steps
        steps = [prep_steps + 1, prep_steps + offset["1"] + 1]
        for name, column in (("preparation.csv", "phase"), ("history.csv", "test")):
            with open(ref / name) as f:
                rows = list(csv.DictReader(f))
            for code in sorted({r[column] for r in rows}):
                stage = [int(float(r["step"])) + offset.get(code, 0) * (column == "test")
                         for r in rows if r[column] == code]
                steps += [stage[0], stage[len(stage) // 2], stage[-1] + 1]
        expected = self.resume_from_checkpoints(scenario, ref, at_least=12, steps=steps)

        # SIGTERM: a checkpoint, an "interrupted" summary naming it, exit 143; then resumed.
        out = self.dir / "term"
        p = subprocess.Popen([GEODEM, "run", str(scenario), "--out", str(out), "--quiet"],
                             stderr=subprocess.PIPE, text=True)
        time.sleep(0.5 * seconds)
        p.send_signal(signal.SIGTERM)
        err = p.communicate(timeout=120)[1]
        if p.returncode != 0:  # (unless it had already finished)
            self.assertEqual(p.returncode, 143, err)
            self.assertIn("--resume", err)
            s = json.loads((out / "summary.json").read_text())
            self.assertEqual(s["status"], "interrupted")
            self.assertTrue(Path(s["results"]["checkpoint"]).is_file())
            r = run("run", str(scenario), "--resume", str(out), "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(output_digests(out), expected)

        # Another scenario's checkpoint is refused, naming the key that differs.
        r = run("run", str(scenario), "--resume", str(ref), "--quiet",
                "--set", "shear.strain_rate=0.06")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("shear.strain_rate", r.stderr)

    def test_pullout_resumes_from_every_stage_bitwise(self):
        # An L anchor under a surcharge plate, with a free front face: every stage of the
        # preparation (foundation, trench fill, cover, consolidation) and the pull.
        text = SMALL_PULLOUT.format(shape="L", trench="trench_depth = 0.05")
        text = text.replace('front = "wall"', 'front = "free"')
        text = text.replace("[pull]", "[surcharge]\npressure = 2000.0\n[pull]")
        text = text.replace("max_displacement = 0.03", "max_displacement = 0.01")
        text += "[output]\nplots = false\n"
        scenario, ref, _ = self.reference(text, 6000)
        # From the first checkpoint in each stage of the preparation and near its middle,
        # and from the first of the pull and the last.
        with open(ref / "preparation.csv") as f:
            rows = list(csv.DictReader(f))
        steps = []
        for code in sorted({r["stage"] for r in rows}):
            stage = [int(float(r["step"])) for r in rows if r["stage"] == code]
            steps += [stage[0], stage[len(stage) // 2]]
        res = json.loads((ref / "summary.json").read_text())["results"]
        steps.append(res["preparation"]["steps"] + 1)
        self.resume_from_checkpoints(scenario, ref, at_least=12, steps=steps)
        self.assertGreater(res["analytic"]["surcharge_measured"], 0.0)
        self.assertGreater(res["preparation"]["fill_grains"], 0)


if __name__ == "__main__":
    GEODEM = cli_case.GEODEM = os.path.abspath(sys.argv.pop(1))
    sys.argv.pop(1)  # REPO_ROOT: the arguments of every command-line test module
    unittest.main(verbosity=2)
