"""Command-line contract: exit codes, error messages, --set, output files, the plotting
child. The scenarios' features through the command line: test_cli_scenarios.py; runs
stopped and resumed from checkpoints: test_cli_checkpoints.py.

Run by CTest: python3 test_cli.py GEODEM_BINARY REPO_ROOT
"""
import csv
import json
import os
import signal
import subprocess
import sys
import time
import unittest
from pathlib import Path

import cli_case
from cli_case import CliCase, run, scene
from small_scenarios import LAB_CHECKPOINT_TRIAXIAL

GEODEM = None
ROOT = None


class CliTest(CliCase):
    def test_version_and_help(self):
        r = run("--version")
        self.assertEqual(r.returncode, 0)
        self.assertIn("geodem", r.stdout)
        self.assertEqual(run("--help").returncode, 0)

    def test_check_examples(self):
        examples = list((ROOT / "examples").glob("*/scenario.toml"))
        examples += list((ROOT / "examples" / "pullout2d").glob("*.toml"))
        for ex in sorted(examples):
            r = run("check", str(ex))
            self.assertEqual(r.returncode, 0, f"{ex}: {r.stderr}")

    def test_run_writes_contract_outputs(self):
        for dim in (2, 3):
            out = self.dir / f"out{dim}"
            r = run("run", self.write(scene(dim)), "--out", str(out), "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
            summary = json.loads((out / "summary.json").read_text())
            for key in ("kind", "geodem_version", "scenario", "results", "timing"):
                self.assertIn(key, summary)
            for key in ("wall_s", "steps", "particles", "particle_steps_per_s", "threads"):
                self.assertIn(key, summary["timing"])
            self.assertEqual(summary["timing"]["particles"], 50)
            # Defaults are part of the resolved settings.
            self.assertEqual(summary["scenario"]["materials"][0]["kt_over_kn"], 0.5)
            with open(out / "history.csv") as f:
                rows = list(csv.reader(f))
            self.assertEqual(rows[0][:4], ["step", "time", "wall_s", "dt"])
            self.assertGreater(len(rows), 2)
            self.assertTrue(all(len(r) == len(rows[0]) for r in rows))
            pvd = (out / "vtk" / "particles.pvd").read_text()
            self.assertIn("particles_000000.vtu", pvd)
            self.assertIn("walls_000000.vtp", pvd)
            vtu = (out / "vtk" / "particles_000001.vtu").read_bytes()
            for name in (b"radius", b"velocity", b"angular_velocity", b"force", b"id"):
                self.assertIn(b'Name="' + name + b'"', vtu)
            self.assertTrue((out / "energy.png").exists())
            self.assertTrue((out / "wall_forces.png").exists())
            self.assertFalse(list(out.glob("**/*.tmp")))

    def test_threads_give_the_same_history(self):
        # 6,000 grains falling into a bed: enough for the step to run on several threads
        # (docs/performance.md); the histories must agree to the last digit.
        text = scene(3).replace("count = 50", "count = 6000").replace("radius = 0.004", "radius = 0.002")
        path = self.write(text)
        histories = {}
        for threads in (1, 2):
            out = self.dir / f"t{threads}"
            env = dict(os.environ, GEODEM_THREADS=str(threads))
            r = subprocess.run([GEODEM, "run", path, "--out", str(out), "--quiet",
                                "--set", "time.duration=0.2", "--set", "output.history_every=100"],
                               capture_output=True, text=True, timeout=300, env=env)
            self.assertEqual(r.returncode, 0, r.stderr)
            s = json.loads((out / "summary.json").read_text())
            self.assertEqual(s["timing"]["threads"], threads)  # from GEODEM_THREADS
            self.assertEqual(s["results"]["particles"], 6000)
            with open(out / "history.csv") as f:
                rows = list(csv.reader(f))
            wall = rows[0].index("wall_s")
            histories[threads] = [r[:wall] + r[wall + 1:] for r in rows]
        self.assertGreater(len(histories[1]), 10)
        contacts = histories[1][0].index("contacts")
        self.assertGreater(int(histories[1][-1][contacts]), 5000)  # a bed has formed
        self.assertEqual(histories[1], histories[2])

    def test_set_overrides(self):
        out = self.dir / "out"
        r = run("run", self.write(scene(2)), "--out", str(out), "--quiet",
                "--set", "time.duration=0.01", "--set", "clouds.0.count=20",
                "--set", "materials.0.name=grit", "--set", "clouds.0.material=grit")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((out / "summary.json").read_text())
        self.assertEqual(s["scenario"]["time"]["duration"], 0.01)
        self.assertEqual(s["results"]["particles"], 20)
        self.assertEqual(s["scenario"]["materials"][0]["name"], "grit")

    def test_unknown_key_suggests(self):
        text = scene(3).replace("friction = 0.5", "frcition = 0.5")
        self.assertBadInput(text, "s.toml:", "materials.0.frcition", "did you mean 'friction'")

    def test_bad_values(self):
        self.assertBadInput(scene(3).replace("young = 1e6", "young = -1e6"), "young",
                            "positive")
        self.assertBadInput(scene(3).replace("young = 1e6", 'young = "stiff"'), "young",
                            "expected a number")
        self.assertBadInput(scene(3).replace("dimension = 3", "dimension = 4"), "dimension")
        self.assertBadInput(scene(3).replace("count = 50", "count = 500000"), "clouds.0",
                            "too dense")
        self.assertBadInput(scene(3).replace('kind = "scene"', 'kind = "bogus"'), "kind")
        self.assertBadInput("kind = \"scene\"\n[time\n", "TOML syntax")
        self.assertBadInput(scene(3), "time.duration", args=("--set", "time.duration=-1"))

    def test_line_numbers(self):
        text = scene(3).replace("count = 50", "count = 2.5")
        line = text.splitlines().index("count = 2.5") + 1
        self.assertBadInput(text, f"s.toml:{line}", "clouds.0.count", "integer")

    def test_missing_and_binary_files(self):
        r = run("check", str(self.dir / "nope.toml"))
        self.assertEqual(r.returncode, 2)
        (self.dir / "bin.toml").write_bytes(b"\x00\x01\x02kind")
        r = run("check", str(self.dir / "bin.toml"))
        self.assertEqual(r.returncode, 2)
        self.assertEqual(run("run").returncode, 2)

    def test_unstable_run_exits_3_and_keeps_outputs(self):
        text = scene(3).replace('step = "auto"', "step = 0.05").replace("duration = 0.05",
                                                                          "duration = 200.0")
        out = self.dir / "out"
        r = run("run", self.write(text), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("time step", r.stderr)
        s = json.loads((out / "summary.json").read_text())
        self.assertEqual(s["status"], "unstable")
        self.assertTrue((out / "history.csv").exists())

    def test_unstable_lab_test_exits_3_naming_its_last_checkpoint(self):
        # The axial wall driven at 100 /s crushes the sample: overlaps beyond the limit.
        text = LAB_CHECKPOINT_TRIAXIAL.replace("strain_rate = 0.05", "strain_rate = 100.0")
        text = text.replace("max_axial_strain = 0.01", "max_axial_strain = 0.5")
        out = self.dir / "out"
        r = run("run", self.write(text + "[checkpoint]\nevery_steps = 5000\n"), "--out",
                str(out), "--quiet")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("last checkpoint", r.stderr)
        s = json.loads((out / "summary.json").read_text())
        self.assertEqual(s["status"], "unstable")
        self.assertIn("overlap", s["results"]["stop_reason"])
        self.assertTrue(Path(s["results"]["checkpoint"]).is_file())

    def test_check_lists_every_problem_by_line(self):
        text = LAB_CHECKPOINT_TRIAXIAL.replace("count = 150", "count = -150")
        text = text.replace("young = 1e8", 'young = "soft"')
        text = text.replace("friction = 0.5", "friction = 0.5\nfrictoin = 0.3")
        text = text.replace("strain_rate = 0.05", "strain_rate = -0.05\ncolour = 1")
        text = text.replace("[output]", "[output]\nplot = false")
        r = run("check", self.write(text))
        self.assertEqual(r.returncode, 2, r.stderr)
        errors = [l for l in r.stderr.splitlines() if l.startswith("error:")]
        keys = ["sample.count", "material.young", "material.frictoin", "shear.strain_rate",
                "shear.colour", "output.plot"]
        self.assertEqual(len(errors), len(keys), r.stderr)
        for line, key in zip(errors, keys):  # in file order
            self.assertIn(f"key '{key}'", line)
        lines = [int(l.split(":")[2]) for l in errors]
        self.assertEqual(lines, sorted(lines))
        self.assertIn("6 problems", r.stderr)
        # A derived default names where it comes from.
        r = run("check", self.write(LAB_CHECKPOINT_TRIAXIAL), "--set", "material.young=1e4")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("defaults to 1 + 2e4 / material.young", r.stderr)

    def test_a_run_too_large_for_the_memory_is_refused_with_its_estimate(self):
        scenario = self.write(LAB_CHECKPOINT_TRIAXIAL)
        out = self.dir / "big"
        env = dict(os.environ, GEODEM_MEMORY_LIMIT="5e7")  # a 50 MB machine
        for args in (["check", scenario, "--set", "sample.count=100000"],
                     ["run", scenario, "--out", str(out), "--set", "sample.count=100000"]):
            r = subprocess.run([GEODEM, *args], capture_output=True, text=True, env=env,
                               timeout=60)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("key 'sample.count': this run needs about", r.stderr)
            self.assertIn("50 MB available", r.stderr)
        self.assertFalse(out.exists())  # refused before anything was written
        r = subprocess.run([GEODEM, "check", scenario], capture_output=True, text=True, env=env,
                           timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr)  # 150 clumps fit

    def test_output_folder_of_an_earlier_run_needs_overwrite(self):
        out = self.dir / "out"
        three = self.write(scene(3) + "vtk_every = 100\n", "s3.toml")
        two = self.write(scene(2) + "vtk_every = 100\n", "s2.toml")
        self.assertEqual(run("run", three, "--out", str(out), "--quiet").returncode, 0)
        frames3 = sorted(p.name for p in (out / "vtk").iterdir())
        r = run("run", two, "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--overwrite", r.stderr)
        self.assertEqual(sorted(p.name for p in (out / "vtk").iterdir()), frames3)  # untouched
        r = run("run", two, "--out", str(out), "--quiet", "--overwrite")
        self.assertEqual(r.returncode, 0, r.stderr)
        summary = json.loads((out / "summary.json").read_text())
        self.assertEqual(summary["scenario"]["dimension"], 2)
        pvd = (out / "vtk" / "particles.pvd").read_text()
        for frame in (out / "vtk").iterdir():  # every frame is the new run's
            self.assertTrue(frame.suffix == ".pvd" or frame.name in pvd, frame.name)
        r = run("run", two, "--resume", str(out), "--overwrite", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        # A folder that holds no run is never emptied.
        other = self.dir / "notes"
        other.mkdir()
        (other / "mine.txt").write_text("keep me")
        r = run("run", two, "--out", str(other), "--quiet", "--overwrite")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("holds no geodem run", r.stderr)
        self.assertEqual((other / "mine.txt").read_text(), "keep me")

    def test_plotting_child(self):
        # Without Python the run still completes, with a warning and no plots.
        out = self.dir / "nopython"
        r = subprocess.run([GEODEM, "run", self.write(scene(2)), "--out", str(out)],
                           capture_output=True, text=True, timeout=300,
                           env={**os.environ, "GEODEM_PYTHON": str(self.dir / "no_python")})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("plotting failed", r.stderr)
        self.assertEqual(json.loads((out / "summary.json").read_text())["status"], "completed")
        self.assertFalse(list(out.glob("*.png")))

        # A run stopped while its plotting child waits: the child leaves without drawing.
        out = self.dir / "stopped"
        p = subprocess.Popen([GEODEM, "run", self.write(scene(2)), "--out", str(out), "--quiet",
                              "--set", "time.duration=1000"], stderr=subprocess.PIPE, text=True)

        def children():
            found = []
            for cmd in Path("/proc").glob("[0-9]*/cmdline"):
                try:
                    args = cmd.read_bytes().split(b"\0")
                except OSError:
                    continue
                if b"--wait" in args and str(out).encode() in args:
                    found.append(cmd.parent.name)
            return found

        deadline = time.time() + 60
        while not children() and time.time() < deadline:
            time.sleep(0.05)
        self.assertTrue(children(), "the run started no plotting child")
        time.sleep(0.5)
        p.send_signal(signal.SIGTERM)
        err = p.communicate(timeout=120)[1]
        self.assertEqual(p.returncode, 143, err)
        self.assertNotIn("Traceback", err)
        self.assertEqual(children(), [])
        self.assertFalse(list(out.glob("*.png")))

    def test_plot_command(self):
        out = self.dir / "out"
        self.assertEqual(run("run", self.write(scene(2)), "--out", str(out), "--quiet").returncode, 0)
        (out / "energy.png").unlink()
        r = run("plot", str(out))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue((out / "energy.png").exists())
        self.assertEqual(run("plot", str(self.dir / "nothing")).returncode, 2)


if __name__ == "__main__":
    GEODEM = cli_case.GEODEM = os.path.abspath(sys.argv.pop(1))
    ROOT = Path(sys.argv.pop(1))
    unittest.main(verbosity=2)
