"""Studies (series, rate_study, calibrate): outputs, resume after a kill, MPI ranks.

Run by CTest: python3 test_studies.py GEODEM_BINARY REPO_ROOT
The studies here are tiny (60 to 240 discs a run) so that they take seconds; the
full-size ones are in examples/studies2d.
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

from small_scenarios import BASE

GEODEM = None
ROOT = None

SERIES = 'kind = "series"\n' + BASE + """
[series]
counts = [60, 120, 240]
seeds = 3
tolerance = 0.05
"""

RATE = 'kind = "rate_study"\n' + BASE + """
[rate_study]
strain_rates = [0.05, 0.1, 0.2]
damping = [0.05, 0.2]
"""

CALIBRATE = ('kind = "calibrate"\n' + BASE.replace("confining_stress = [1e5]",
                                                   "confining_stress = [5e4, 1e5, 2e5]") + """
[targets]
phi_peak_deg = 22.0
[calibrate]
seeds = 1
verify_seeds = 2
max_iterations = 2
name = "tiny"
""")


def run(*args, env=None):
    return subprocess.run([GEODEM, *args], capture_output=True, text=True, timeout=600, env=env)


def results(out):
    return json.loads((Path(out) / "summary.json").read_text())["results"]


class StudyTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, text, name="study.toml"):
        p = self.dir / name
        p.write_text(text)
        return str(p)

    def test_series_outputs(self):
        out = self.dir / "out"
        r = run("run", self.write(SERIES), "--out", str(out), "--threads", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((out / "summary.json").read_text())
        self.assertEqual(s["kind"], "series")
        res = s["results"]
        self.assertEqual([g["count"] for g in res["groups"]], [60, 120, 240])
        self.assertTrue(all(g["runs"] == 3 for g in res["groups"]))
        # d0/L falls as count^(-1/2) at the same grain size.
        x = [g["d0_over_L"] for g in res["groups"]]
        self.assertAlmostEqual(x[0] / x[2], 2.0, delta=0.1)
        for key in ("extrapolated", "mean_fit", "std_fit", "count_for_tolerance",
                    "smallest_tested_count", "failed_runs"):
            self.assertIn(key, res)
        self.assertEqual(res["failed_runs"], [])
        rows = (out / "runs.csv").read_text().splitlines()
        self.assertEqual(len(rows), 1 + 9)
        # Each run is re-runnable alone and gives the same result.
        run_dir = out / "runs" / "n120_seed2"
        alone = self.dir / "alone"
        r = run("run", str(run_dir / "scenario.toml"), "--out", str(alone), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(results(alone)["peak_q"], results(run_dir)["peak_q"])

    def test_rate_study_outputs(self):
        out = self.dir / "out"
        r = run("run", self.write(RATE), "--out", str(out), "--threads", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = results(out)
        for key in ("quasi_static", "k", "fit", "per_damping", "runs"):
            self.assertIn(key, res)
        self.assertEqual(len(res["runs"]), 6)
        # Inertial number I = rate d0 sqrt(rho / p): proportional to the rate.
        by_rate = {run["strain_rate"]: run["inertial_number"] for run in res["runs"]}
        self.assertAlmostEqual(by_rate[0.2] / by_rate[0.05], 4.0, places=9)

    def test_interrupted_series_resumes_without_redoing_finished_runs(self):
        study = self.write(SERIES)
        fresh = self.dir / "fresh"
        r = run("run", study, "--out", str(fresh), "--threads", "1", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        for attempt in range(3):
            out = self.dir / f"killed{attempt}"
            p = subprocess.Popen([GEODEM, "run", study, "--out", str(out), "--threads", "1",
                                  "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            deadline = time.time() + 120
            done = []
            # Kill after one to three runs are finished.
            while time.time() < deadline and p.poll() is None:
                done = list(out.glob("runs/*/summary.json"))
                if len(done) >= attempt + 1:
                    break
                time.sleep(0.005)
            p.send_signal(signal.SIGKILL)
            p.wait()
            done = {f: (f.stat().st_mtime_ns, f.read_bytes()) for f in out.glob("runs/*/summary.json")}
            if not done or (out / "summary.json").exists():
                continue  # killed too early or too late: try the next attempt
            r = run("run", study, "--resume", str(out), "--threads", "2", "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
            for f, (mtime, content) in done.items():
                self.assertEqual(f.stat().st_mtime_ns, mtime, f"{f} was run again")
                self.assertEqual(f.read_bytes(), content)
            s = json.loads((out / "summary.json").read_text())
            self.assertEqual(s["timing"]["runs_reused"], len(done))
            self.assertEqual(s["results"], results(fresh))
            return
        self.fail("no attempt interrupted the study mid-way")

    def test_killed_study_continues_its_unfinished_runs_from_their_checkpoints(self):
        # One run at a time, a checkpoint every 1,000 steps: killed mid-run, the study's
        # rerun continues that run from its checkpoint and ends as one never stopped.
        study = self.write(SERIES.replace("seeds = 3", "seeds = 1") +
                           "[checkpoint]\nevery_steps = 1000\n")
        fresh = self.dir / "fresh"
        r = run("run", study, "--out", str(fresh), "--threads", "1", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(list(fresh.glob("runs/*/checkpoint")), [])  # deleted when done
        out = self.dir / "killed"
        p = subprocess.Popen([GEODEM, "run", study, "--out", str(out), "--threads", "1",
                              "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + 120
        while time.time() < deadline and p.poll() is None:
            if any(out.glob("runs/*/checkpoint/checkpoint_*.bin")):
                break
            time.sleep(0.005)
        time.sleep(0.2)
        p.send_signal(signal.SIGKILL)
        p.wait()
        self.assertFalse((out / "summary.json").exists(), "the study ended before the kill")
        r = run("run", study, "--resume", str(out), "--threads", "1", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("resuming from", r.stderr)
        self.assertEqual(results(out), results(fresh))
        for f in fresh.glob("runs/*/history.csv"):
            self.assertEqual((out / f.relative_to(fresh)).read_bytes(), f.read_bytes(), f)

    def test_changed_runs_are_not_reused(self):
        study = self.write(SERIES)
        out = self.dir / "out"
        self.assertEqual(run("run", study, "--out", str(out), "--quiet").returncode, 0)
        r = run("run", study, "--resume", str(out), "--quiet", "--set", "material.friction_deg=25")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((out / "summary.json").read_text())
        self.assertEqual(s["timing"]["runs_reused"], 0)
        r = run("run", study, "--resume", str(out), "--quiet", "--set", "material.friction_deg=25")
        self.assertEqual(json.loads((out / "summary.json").read_text())["timing"]["runs_reused"], 9)

    def test_mpi_ranks_give_the_same_results_as_one_process(self):
        mpirun = shutil.which("mpirun")
        version = run("--version").stdout
        if not mpirun or "(MPI)" not in version:
            self.skipTest("geodem built without MPI, or no mpirun")
        study = self.write(SERIES)
        one, two = self.dir / "one", self.dir / "two"
        r = run("run", study, "--out", str(one), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
        r = subprocess.run([mpirun, "-n", "2", GEODEM, "run", study, "--out", str(two),
                            "--quiet"], capture_output=True, text=True, timeout=600, env=env)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        s = json.loads((two / "summary.json").read_text())
        self.assertEqual(s["timing"]["ranks"], 2)
        self.assertEqual(s["results"], results(one))

    def test_calibration_writes_a_usable_material_file(self):
        out = self.dir / "out"
        r = run("run", self.write(CALIBRATE), "--out", str(out), "--threads", "2", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((out / "summary.json").read_text())
        self.assertIn(s["status"], ("completed", "not_converged"))
        res = s["results"]
        self.assertLessEqual(len(res["iterations"]), 2)
        self.assertIn("phi_peak_deg", res["verification"]["checks"])
        self.assertEqual(res["upscaling"]["grain_size_factor"], 2.0)
        material = out / "material.toml"
        text = material.read_text()
        self.assertIn('name = "tiny"', text)
        # A triaxial test with the file gives the micro parameters of the search.
        scenario = 'kind = "triaxial"\n' + BASE.replace(
            '[material]\ndensity = 2650.0\nyoung = 1e8\nkt_over_kn = 0.5\nfriction_deg = 30.0',
            f'[material]\nfile = "{material}"')
        tri = self.dir / "tri"
        r = run("run", self.write(scenario, "tri.toml"), "--out", str(tri), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        used = json.loads((tri / "summary.json").read_text())["scenario"]["material"]
        self.assertAlmostEqual(used["friction_deg"], res["micro"]["friction_deg"], places=9)

    def test_bad_study_input(self):
        cases = {
            "one count": SERIES.replace("counts = [60, 120, 240]", "counts = [60]"),
            "unknown key": SERIES.replace("seeds = 3", "seed = 3"),
            "missing table": SERIES.split("[series]")[0],
            "two stresses": SERIES.replace("confining_stress = [1e5]", "confining_stress = [1e5, 2e5]"),
            "no rates": RATE.replace("strain_rates = [0.05, 0.1, 0.2]", "strain_rates = []"),
            "no phi target": CALIBRATE.replace("phi_peak_deg = 22.0", "cohesion = 0.0"),
            "cohesion without bonds": CALIBRATE.replace("phi_peak_deg = 22.0",
                                                        "phi_peak_deg = 22.0\ncohesion = 5e3"),
        }
        for name, text in cases.items():
            with self.subTest(name):
                f = self.write(text, "bad.toml")
                r = run("check", f)
                self.assertEqual(r.returncode, 2, f"{name}: {r.stdout} {r.stderr}")
                self.assertIn("bad.toml", r.stderr)
        self.assertEqual(run("check", self.write(SERIES)).returncode, 0)


if __name__ == "__main__":
    GEODEM = os.path.abspath(sys.argv.pop(1))
    ROOT = Path(sys.argv.pop(1))
    unittest.main(verbosity=2)
