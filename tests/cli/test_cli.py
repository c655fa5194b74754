"""Command-line contract: exit codes, error messages, --set, output files.

Run by CTest: python3 test_cli.py GEODEM_BINARY REPO_ROOT
"""
import csv
import hashlib
import json
import math
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

from small_scenarios import (CHECKPOINT_SCENE, LAB_CHECKPOINT_TRIAXIAL, SMALL_PULLOUT,
                             SMALL_SCENE)
from test_stages import read_vtk

GEODEM = None
ROOT = None


def scene(dim):
    if dim == 3:
        return SMALL_SCENE.format(dim=3, gravity="[0, 0, -9.81]", normal="[0, 0, 1]",
                                  lo="[0, 0, 0]", hi="[0.1, 0.1, 0.1]")
    return SMALL_SCENE.format(dim=2, gravity="[0, -9.81]", normal="[0, 1]",
                              lo="[0, 0]", hi="[0.1, 0.1]")


def run(*args):
    return subprocess.run([GEODEM, *args], capture_output=True, text=True, timeout=300)


class CliTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, text, name="s.toml"):
        p = self.dir / name
        p.write_text(text)
        return str(p)

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

    def test_periodic_biaxial_writes_its_cell(self):
        # The small biaxial test in a periodic cell: no walls; the cell's edges in each VTK
        # frame with its stress, the lateral stress at the last confining stress at the end.
        text = LAB_CHECKPOINT_TRIAXIAL.replace("count = 150", 'count = 150\nboundary = "periodic"')
        out = self.dir / "periodic"
        r = run("run", self.write(text), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        results = json.loads((out / "summary.json").read_text())["results"]
        self.assertEqual(len(results["tests"]), 2)
        pvd = (out / "vtk" / "particles.pvd").read_text()
        self.assertNotIn("walls_", pvd)
        frames = sorted((out / "vtk").glob("cell_*.vtp"))
        self.assertGreater(len(frames), 2)
        root, arrays = read_vtk(frames[-1])
        self.assertEqual(root.find(".//Piece").get("NumberOfLines"), "4")
        self.assertEqual(len(arrays["stress"]), 4 * 9)
        sxx, syy = arrays["stress"][0], arrays["stress"][4]
        self.assertLess(abs(sxx / 1e5 - 1.0), 0.02)
        self.assertGreater(syy, sxx)

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

    def assertBadInput(self, text, *fragments, args=()):
        path = self.write(text)
        r = run("check", path, *args)
        self.assertEqual(r.returncode, 2, f"expected exit 2, got {r.returncode}: {r.stderr}")
        for frag in fragments:
            self.assertIn(frag, r.stderr)
        return r

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

    def test_clumps_bonds_and_rolling_in_a_scene(self):
        text = scene(3).replace("friction = 0.5", """friction = 0.5
rolling_friction = 0.1
normal_cohesion = 1e4
shear_cohesion = 1e4""") + """
[[templates]]
name = "tri"
members = [[0, 0, 0, 0.004], [0.005, 0, 0, 0.003], [0.002, 0.004, 0, 0.003]]
[[clumps]]
template = "tri"
position = [0.05, 0.05, 0.2]
axis = [1, 0, 0]
angle_deg = 30
[[particles]]
position = [0.0, 0.5, 0.5]
radius = 0.01
[[particles]]
position = [0.02, 0.5, 0.5]
radius = 0.01
[bonds]
create = "initial"
"""
        text = text.replace("[[clouds]]", "[[clouds]]\ngrain = \"pair_0.9\"").replace(
            "count = 50\nradius = 0.004", "count = 20\nradius = 0.002")
        out = self.dir / "out"
        r = run("run", self.write(text), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        self.assertEqual(res["clumps"], 21)
        self.assertEqual(res["particles"], 2 + 3 + 40)
        self.assertEqual(res["bonds_created"], 1)  # the two touching grains
        with open(out / "history.csv") as f:
            header = next(csv.reader(f))
        self.assertIn("bonds", header)
        self.assertIn("broken_bonds", header)
        vtu = (out / "vtk" / "particles_000001.vtu").read_bytes()
        self.assertIn(b'Name="clump"', vtu)

    def test_clump_input_errors(self):
        self.assertBadInput(scene(3).replace("[[clouds]]", "[[clouds]]\ngrain = \"blob\""),
                            "clouds.0.grain", "unknown grain 'blob'", "pair_0.9")
        self.assertBadInput(scene(3) + "[[templates]]\nname = \"t\"\nmembers = [[0, 0, 1]]\n",
                            "templates.0.members")
        self.assertBadInput(scene(3).replace('young = 1e6', 'law = "hertz"\nyoung = 1e6\n'
                                             'normal_cohesion = 1.0'), "normal_cohesion",
                            "linear")

    def test_biaxial_with_clumps_and_bonds(self):
        text = (ROOT / "examples" / "grain_shape2d" / "base.toml").read_text().format(
            seed=1, grain="pair_0.9", friction=0.5, rolling=0.1, cohesion=5e4, porosity=0.25,
            confining="[1e5]")
        text = text.replace("count = 1000", "count = 150").replace("box = [1.0, 2.0]",
                                                                    "box = [0.4, 0.8]")
        text = text.replace("max_axial_strain = 0.10", "max_axial_strain = 0.01")
        out = self.dir / "out"
        r = run("run", self.write(text), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((out / "summary.json").read_text())
        res = s["results"]
        self.assertEqual(res["grains"], 150)
        self.assertEqual(s["timing"]["particles"], 300)
        self.assertGreater(res["preparation"]["bonds"], 100)
        self.assertLessEqual(res["porosity_initial"], 0.26)
        with open(out / "history.csv") as f:
            rows = list(csv.DictReader(f))
        self.assertGreater(float(rows[-1]["bonds"]), 0)
        self.assertGreater(res["peak_q"], 0)

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

    def test_particle_file(self):
        (self.dir / "grains.txt").write_text("# id x y z\n1 0.05 0.05 0.01\n2, 0.05, 0.05, 0.03\n")
        text = scene(3).replace("[[clouds]]", "[[particle_files]]\nfile = \"grains.txt\"\n"
                                "columns = [\"id\", \"x\", \"y\", \"z\"]\nradius = 0.005\n\n[[clouds]]")
        out = self.dir / "out"
        r = run("run", self.write(text), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(json.loads((out / "summary.json").read_text())["results"]["particles"], 52)
        (self.dir / "grains.txt").write_text("1 0.05 0.05 oops\n")
        self.assertBadInput(text, "grains.txt:1", "oops")

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

    def test_pullout_deposit_cache_gives_the_runs_bit_for_bit(self):
        # The foundation stored by one run and loaded by the next, and by a run of another
        # anchor on the same foundation: every output as without the cache; another grain
        # size deposits its own.
        text = SMALL_PULLOUT.format(shape="L", trench="trench_depth = 0.05")
        text = text.replace("max_displacement = 0.03", "max_displacement = 0.01")
        text += "[output]\nplots = false\n"
        scenario = self.write(text)
        cache = f"soil.deposit_cache={self.dir / 'cache'}"

        def go(name, *extra):
            out = self.dir / name
            r = run("run", scenario, "--out", str(out), "--quiet", *extra)
            self.assertEqual(r.returncode, 0, r.stderr)
            return out, json.loads((out / "summary.json").read_text())["results"]

        def same(a, b):
            for f in ("history.csv", "preparation.csv", "tension_profiles.csv",
                      "states/grains_final.csv", "states/sheet_final.csv"):
                self.assertEqual((a / f).read_bytes(), (b / f).read_bytes(), f)

        plain, res = go("plain")
        # The sheet's parts telescope: what run-out, bend and trench part take off the
        # sheet sums to the clamp's tension, row by row.
        with open(plain / "history.csv") as f:
            for row in csv.DictReader(f):
                parts = sum(float(row[p + "_carried"]) for p in ("runout", "bend", "trench"))
                self.assertAlmostEqual(parts, float(row["tension"]),
                                       delta=1e-9 * abs(float(row["tension"])) + 1e-9)
        at_max = res["sheet_parts"]["at_T_max"]
        self.assertGreater(at_max["trench"]["normal"], 0.0)
        self.assertAlmostEqual(sum(at_max[p]["carried"] for p in ("runout", "bend", "trench")),
                               res["T_max"], delta=1e-9 * res["T_max"])
        self.assertAlmostEqual(res["sheet_parts"]["slip_estimate"]["bend"]["tension_ratio"],
                               res["analytic"]["capstan_factor"])
        stored, res_stored = go("stored", "--set", cache)
        loaded, res_loaded = go("loaded", "--set", cache)
        self.assertTrue(res_stored["preparation"]["deposit_cache"].startswith("stored "))
        self.assertTrue(res_loaded["preparation"]["deposit_cache"].startswith("loaded "))
        same(plain, stored)
        same(plain, loaded)
        self.assertEqual(res_loaded["T_max"], res["T_max"])
        other = ("--set", "anchor.runout_length=0.4", "--set", "anchor.trench_depth=0.07")
        other_cached, res_other = go("other_cached", *other, "--set", cache)
        self.assertTrue(res_other["preparation"]["deposit_cache"].startswith("loaded "))
        same(go("other_plain", *other)[0], other_cached)
        _, res_fine = go("fine", "--set", "soil.radius=0.009", "--set", cache)
        self.assertTrue(res_fine["preparation"]["deposit_cache"].startswith("stored "))
        self.assertEqual(len(list((self.dir / "cache").glob("pullout_foundation_*.bin"))), 2)

    def test_pullout_runout_against_the_slippage_estimate(self):
        out = self.dir / "out"
        r = run("run", self.write(SMALL_PULLOUT.format(shape="runout", trench="")),
                "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((out / "summary.json").read_text())
        res = s["results"]
        for key in ("T_max", "displacement_at_T_max", "T_analytic_slip",
                    "soil_displacement_mean"):
            self.assertIn(key, res)
        # Slippage: T_max within 20 % of the estimate, the soil moves far less than the sheet.
        ratio = res["T_max"] / res["T_analytic_slip"]
        print(f"[ measured ] small run-out: T_max / T_analytic_slip = {ratio:.3f}")
        self.assertLess(abs(ratio - 1.0), 0.2)
        self.assertLess(res["soil_displacement_mean"], 0.5 * 0.03)
        with open(out / "history.csv") as f:
            rows = list(csv.DictReader(f))
        self.assertGreater(len(rows), 100)
        self.assertTrue(all(float(r["tension"]) >= 0.0 for r in rows))
        self.assertAlmostEqual(float(rows[-1]["displacement"]), 0.03, delta=1e-3)
        # A run-out has no bend: the whole tension comes off the run-out part.
        for row in rows:
            self.assertAlmostEqual(float(row["runout_carried"]), float(row["tension"]),
                                   delta=1e-9 * abs(float(row["tension"])) + 1e-9)
            self.assertEqual(float(row["bend_carried"]) + float(row["trench_carried"]), 0.0)
        for name in ("pullout.png", "tension_profiles.png", "pullout_initial.png",
                     "pullout_final.png", "tension_profiles.csv", "states/grains_final.csv",
                     "states/sheet_initial.csv"):
            self.assertTrue((out / name).exists(), name)
        pvd = (out / "vtk" / "particles.pvd").read_text()
        self.assertIn("spars_000000.vtp", pvd)

    def test_pullout_sheet_node_mass_factor(self):
        # A given factor replaces the estimate; at 1 (the sheet's true mass) the automatic
        # time step must respect a node on its two elements alone: dt <= safety x
        # sqrt(2 m / (2 J / l)), m = 0.5 kg/m2 x l (l = 2 x 8 mm, J = 1e5 N/m, safety 0.8).
        text = SMALL_PULLOUT.format(shape="runout", trench="").replace(
            "max_displacement = 0.03", "max_displacement = 0.002")
        dts, factors = {}, {}
        for name, extra in (("estimate", ()), ("true_mass", ("--set", "sheet.node_mass_factor=1"))):
            out = self.dir / name
            r = run("run", self.write(text), "--out", str(out), "--quiet", *extra)
            self.assertEqual(r.returncode, 0, r.stderr)
            res = json.loads((out / "summary.json").read_text())["results"]
            dts[name] = res["dt"]
            factors[name] = res["sheet"]["node_mass_factor"]
            if name == "true_mass":
                self.assertEqual(res["sheet"]["node_mass_factor"], 1.0)
            else:
                self.assertGreater(res["sheet"]["node_mass_factor"], 1.0)
        l, J = 0.016, 1e5
        # The estimate sizes a node (2 J / l + 2 E of stiffness) to the grains' critical step
        # in their packing: its own step, scaled, lies at most about twice the run's (more
        # would be a sheet heavier than needed, which roughens the interface:
        # docs/lab_tests.md, "The sheet's inertia"), and never below it.
        f = factors["estimate"]
        node_step = 0.8 * math.sqrt(2.0 * f * 0.5 * l / (2.0 * J / l + 2.0 * 2e7))
        print(f"[ measured ] node mass factor {f:.4g}: the node's scaled step "
              f"{node_step / dts['estimate']:.3f} x the run's")
        self.assertGreaterEqual(node_step, dts["estimate"])
        self.assertLess(node_step, 2.0 * dts["estimate"])
        bound = 0.8 * math.sqrt(2.0 * 0.5 * l / (2.0 * J / l))
        print(f"[ measured ] pull-out dt: estimate {dts['estimate']:.3g} s, true sheet mass "
              f"{dts['true_mass']:.3g} s (bound {bound:.3g} s)")
        self.assertLessEqual(dts["true_mass"], bound)
        self.assertLess(dts["true_mass"], dts["estimate"])
        self.assertBadInput(text.replace("[sheet]", "[sheet]\nnode_mass_factor = 0.5"),
                            "node_mass_factor", "1 or more")
        self.assertBadInput(text.replace(
            "[sheet]", "[sheet]\nnode_mass_factor = 10\nmass_scaling = false"),
            "node_mass_factor", "mass_scaling")

    def test_scene_with_a_chain(self):
        text = (Path(__file__).parent / "chain_scene.toml").read_text()
        text = text.replace("duration = 3.0 ", "duration = 0.5 ")
        out = self.dir / "out"
        r = run("run", self.write(text), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        cable = res["chains"]["cable"]
        self.assertEqual(cable["nodes"], 61)
        self.assertGreater(cable["tension_max"], 0.0)
        with open(out / "history.csv") as f:
            header = next(csv.reader(f))
        self.assertIn("chain_cable_tension_first", header)
        self.assertIn("spars_000000.vtp", (out / "vtk" / "particles.pvd").read_text())
        self.assertBadInput(text.replace("held = [0, -1]", "held = [0, 99]"), "held", "99")
        self.assertBadInput(text.replace("held = [0, -1]", "velocity = [0.1, 0]"), "velocity",
                            "held")
        self.assertBadInput(text.replace('material = "sheet"', 'material = "steel"'),
                            "chains.0.material", "steel")

    def test_pullout_input_errors(self):
        text = SMALL_PULLOUT.format(shape="L", trench="trench_depth = 0.2")
        self.assertBadInput(text, "trench_depth", "shallower")
        self.assertBadInput(SMALL_PULLOUT.format(shape="U", trench=""), "anchor.shape", "runout")
        text = SMALL_PULLOUT.format(shape="L", trench="trench_depth = 0.05\ntrench_width = 0.5")
        self.assertBadInput(text, "trench_width", "inside the box")
        self.assertBadInput(SMALL_PULLOUT.format(shape="runout", trench="").replace(
            "cover = 0.1", "cover = 0.01"), "anchor.cover", "grain diameter")
        text = SMALL_PULLOUT.format(shape="L", trench="trench_depth = 0.02")  # 10 mm wide
        self.assertBadInput(text, "anchor.trench_width", "narrower than the largest grain")

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
    GEODEM = os.path.abspath(sys.argv.pop(1))
    ROOT = Path(sys.argv.pop(1))
    unittest.main(verbosity=2)
