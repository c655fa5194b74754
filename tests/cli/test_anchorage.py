"""Interface shear, interface calibration and pull-outs over seeds, through the command
line: the quick versions of docs/anchorage_design.md's cases.

Run by CTest: python3 test_anchorage.py GEODEM_BINARY REPO_ROOT
"""
import csv
import json
import math
import os
import subprocess
import sys
import tomllib
import unittest
from pathlib import Path

from cli_case import CliCase
from small_scenarios import shear

GEODEM = None
ROOT = None

# A small run-out box (its [sheet] table open last, for the caller's sheet keys).
SMALL_RUNOUT = """[box]
length = 0.6
foundation = 0.08
[soil]
density = 2600.0
young = 2e7
friction_deg = 30.0
radius = 0.008
[anchor]
runout_length = 0.35
cover = 0.06
[sheet]
interface_friction_deg = 20.0
"""

def run(*args, timeout=600):
    return subprocess.run([GEODEM, *args], capture_output=True, text=True, timeout=timeout)


class AnchorageTest(CliCase):  # (a temporary folder per test and write())
    def test_check_examples(self):
        for ex in sorted((ROOT / "examples" / "interface_shear2d").glob("*.toml")):
            r = run("check", str(ex))
            self.assertEqual(r.returncode, 0, f"{ex}: {r.stderr}")

    def test_rigid_base_gives_the_local_friction(self):
        # Clumps lying on a flat rigid sheet slide on it without rolling: every contact at
        # the Coulomb limit, so the envelope's friction is the local one.
        out = self.dir / "rigid"
        r = run("run", self.write(shear()), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        print(f"[ measured ] rigid base, local 25 deg: macro {res['interface_friction_peak_deg']:.3f}"
              f" deg (residual {res['interface_friction_residual_deg']:.3f})")
        self.assertAlmostEqual(res["interface_friction_residual_deg"], 25.0, delta=0.5)
        self.assertAlmostEqual(res["interface_adhesion_residual"], 0.0, delta=300.0)
        # The contract's names: the peak envelope and the mean secant stiffness.
        self.assertEqual(res["interface_phi_deg"], res["interface_friction_peak_deg"])
        self.assertEqual(res["interface_adhesion"], res["interface_adhesion_peak"])
        stiffness = [t["shear_stiffness"] for t in res["tests"]]
        self.assertAlmostEqual(res["interface_stiffness"], sum(stiffness) / len(stiffness),
                               delta=1e-9 * max(stiffness))
        self.assertGreater(res["interface_stiffness"], 0.0)
        for t in res["tests"]:
            self.assertLess(t["servo_error_max"], 0.01)
            self.assertAlmostEqual(t["normal_stress"] / t["normal_stress_target"], 1.0, delta=0.01)
        for name in ("history.csv", "interface_shear.png", "interface_envelope.png"):
            self.assertTrue((out / name).exists(), name)
        with open(out / "history.csv") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual({r["test"] for r in rows}, {"0", "1"})

    def test_soil_base_holds_the_normal_stress(self):
        out = self.dir / "soil"
        r = run("run", self.write(shear(base="soil")), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        for t in res["tests"]:
            print(f"[ measured ] soil base at {t['normal_stress_target'] / 1e3:g} kPa: servo error"
                  f" mean {t['servo_error_mean']:.4f}, max {t['servo_error_max']:.4f}")
            self.assertLess(t["servo_error_mean"], 0.01)
            self.assertGreater(t["peak_shear_stress"], 0.0)
        self.assertTrue(res["peak_envelope"]["fitted"])

    def test_constant_normal_stiffness_moves_the_normal_stress_with_the_plate(self):
        # With shear.normal_stiffness = k the plate's target is sigma0 + k x its rise: the
        # small soil contracts as it is sheared, so the normal stress falls with the plate.
        k = 5e6
        text = shear(base="soil").replace("[shear]\n", f"[shear]\nnormal_stiffness = {k}\n")
        out = self.dir / "cns"
        r = run("run", self.write(text), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        self.assertEqual(res["normal_stiffness"], k)
        with open(out / "history.csv") as f:
            rows = list(csv.DictReader(f))
        for test, sigma0 in (("0", 10e3), ("1", 20e3)):
            prev, moved = 0.0, 0.0
            for row in (r for r in rows if r["test"] == test):
                sig, target = float(row["normal_stress"]), float(row["normal_stress_target"])
                rise = float(row["dilation"])
                # The servo holds the moving target within 1 % of sigma0 in every row.
                self.assertLess(abs(sig - target), 0.01 * sigma0)
                # The row's mean target against the law at the row's mid rise: within half
                # the row's own change of k x rise (the target moves with the plate inside
                # the row: a collapse of the soil can lower it by 10 % of sigma0 in one
                # row) and 1 % of sigma0.
                law = sigma0 + k * 0.5 * (prev + rise)
                self.assertLess(abs(target - law), 0.5 * k * abs(rise - prev) + 0.01 * sigma0)
                prev, moved = rise, max(moved, abs(sig - sigma0))
            self.assertGreater(moved, 0.1 * sigma0)  # the stiffness did act
        for t in res["tests"]:
            self.assertAlmostEqual(t["peak_stress_ratio"],
                                   t["peak_shear_stress"] / t["normal_stress_at_peak"])
            self.assertLess(t["servo_error_max"], 0.01)

    def test_deposit_cache_gives_the_runs_bit_for_bit(self):
        # A deposit stored by one run and loaded by the next (and by a run of other normal
        # stresses): every output as without the cache. A damaged file is a miss.
        def go(name, text, cache=True):
            out = self.dir / name
            args = ["--set", f"soil.deposit_cache={self.dir / 'cache'}"] if cache else []
            r = run("run", self.write(text, name + ".toml"), "--out", str(out), "--quiet", *args)
            self.assertEqual(r.returncode, 0, r.stderr)
            return out, json.loads((out / "summary.json").read_text())["results"], r.stderr

        base = shear(base="soil")
        plain, res_plain, _ = go("plain", base, cache=False)
        stored, res_stored, _ = go("stored", base)
        loaded, res_loaded, _ = go("loaded", base)
        self.assertTrue(res_stored["deposit_cache"].startswith("stored "))
        self.assertTrue(res_loaded["deposit_cache"].startswith("loaded "))
        for out in (stored, loaded):
            self.assertEqual((out / "history.csv").read_bytes(),
                             (plain / "history.csv").read_bytes())
        other = base.replace("[10e3, 20e3]", "[15e3]")
        _, res_other, _ = go("other", other)
        _, res_other_plain, _ = go("other_plain", other, cache=False)
        self.assertTrue(res_other["deposit_cache"].startswith("loaded "))
        self.assertEqual(res_other["tests"], res_other_plain["tests"])
        cached = list((self.dir / "cache").glob("*.bin"))
        self.assertEqual(len(cached), 1)
        cached[0].write_bytes(cached[0].read_bytes()[:100])
        damaged, res_damaged, err = go("damaged", base)
        self.assertIn("unusable", err)
        self.assertTrue(res_damaged["deposit_cache"].startswith("stored "))
        self.assertEqual((damaged / "history.csv").read_bytes(),
                         (plain / "history.csv").read_bytes())

    def test_input_errors(self):
        for text, key, fragment in (
                (shear().replace("height = 0.05", "height = 0.01"), "box", "3 grains"),
                (shear().replace('base = "rigid"', 'base = "sand"'), "box.base", "rigid"),
                (shear().replace("[10e3, 20e3]", "[10e3, -1]"), "shear.normal_stress", "> 0"),
                (shear(base="soil", travel=0.15), "shear.max_displacement", "embedded")):
            r = run("check", self.write(text))
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(key, r.stderr)
            self.assertIn(fragment, r.stderr)

    def test_interface_calibration_writes_a_material_the_pullout_reads(self):
        text = 'kind = "calibrate"\n' + shear(base="rigid").replace(
            'kind = "interface_shear"\n', "") + """
[targets]
interface_friction_deg = 28.0
[calibrate]
name = "box_soil"
seeds = 1
verify_seeds = 1
max_iterations = 4
"""
        out = self.dir / "cal"
        r = run("run", self.write(text, "cal.toml"), "--out", str(out), "--quiet", "--threads", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        print(f"[ measured ] interface calibration to 28 deg on a rigid base: local "
              f"{res['local_friction_deg']:.2f} deg, verified "
              f"{res['verification']['macro']['interface_friction_deg']:.2f} deg")
        self.assertTrue(res["converged"])
        self.assertAlmostEqual(res["local_friction_deg"], 28.0, delta=1.0)
        material = (out / "material.toml").read_text()
        self.assertIn("[interface]", material)
        self.assertTrue((out / "interface_calibration.png").exists())
        # A pull-out naming the file takes the local friction for its sheet and the
        # macroscopic one for its design estimate.
        pullout = f"""
kind = "pullout"
[box]
length = 0.8
foundation = 0.12
[soil]
file = "{out / 'material.toml'}"
radius = 0.008
[anchor]
runout_length = 0.5
cover = 0.1
[pull]
max_displacement = 0.002
history_points = 10
[output]
vtk = false
plots = false
"""
        po = self.dir / "po"
        r = run("run", self.write(pullout, "po.toml"), "--out", str(po), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((po / "summary.json").read_text())
        self.assertAlmostEqual(s["scenario"]["sheet"]["interface_friction_deg"],
                               res["local_friction_deg"], places=6)
        self.assertAlmostEqual(s["results"]["analytic"]["interface_friction_deg"],
                               res["verification"]["macro"]["interface_friction_deg"], places=6)

    def test_pullout_over_seeds(self):
        pullout = """
kind = "pullout"
seed = 4
seeds = 3
""" + SMALL_RUNOUT + """[pull]
max_displacement = 0.01
history_points = 20
[analytic]
soil_friction_deg = 30.0
"""
        out = self.dir / "seeds"
        r = run("run", self.write(pullout, "po.toml"), "--out", str(out), "--quiet",
                "--threads", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        t = res["T_max"]
        self.assertEqual(t["count"], 3)
        with open(out / "pullout_runs.csv") as f:
            rows = list(csv.DictReader(f))
        tmax = [float(r["T_max"]) for r in rows]
        self.assertEqual([int(float(r["seed"])) for r in rows], [4, 5, 6])
        self.assertAlmostEqual(t["mean"], sum(tmax) / 3, delta=1e-9 * t["mean"])
        self.assertAlmostEqual(t["min"], min(tmax))
        self.assertLess(t["min"], t["max"])  # three different packings
        self.assertTrue((out / "pullout_seeds.png").exists())
        for k in (4, 5, 6):
            self.assertTrue((out / "runs" / f"seed{k}" / "history.csv").exists())
        # T_residual: the mean of the history rows over the pull's second half (rows equally
        # spaced in displacement), per run and as the series' statistics.
        residual = [float(r["T_residual"]) for r in rows]
        for k, value in zip((4, 5, 6), residual):
            with open(out / "runs" / f"seed{k}" / "history.csv") as f:
                late = [float(h["tension"]) for h in csv.DictReader(f)
                        if float(h["displacement"]) >= 0.005]
            self.assertGreaterEqual(len(late), 5)
            self.assertAlmostEqual(value, sum(late) / len(late), delta=1e-9 * value)
            self.assertLessEqual(value, tmax[(k - 4)])
        self.assertAlmostEqual(res["T_residual"]["mean"], sum(residual) / 3,
                               delta=1e-9 * res["T_residual"]["mean"])

    def test_a_thick_sheet_is_covered_without_overlap(self):
        # A sheet half a grain radius thick: each layer's cloud of grains starts above the
        # sheet, not at the top of the grains under it (from there the smallest grains
        # overlapped the sheet by two thirds of their radius, and the run stopped as unstable).
        pullout = """
kind = "pullout"
seed = 4
""" + SMALL_RUNOUT.replace("radius = 0.008", "radius = 0.004") + """element_length = 0.008
bending_stiffness = 0.5
thickness = 0.002
[pull]
max_displacement = 0.004
history_points = 10
[analytic]
soil_friction_deg = 30.0
"""
        out = self.dir / "thick"
        r = run("run", self.write(pullout, "po.toml"), "--out", str(out), "--quiet",
                "--threads", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        s = json.loads((out / "summary.json").read_text())
        self.assertEqual(s["status"], "completed")
        self.assertGreater(s["results"]["preparation"]["fill_grains"], 0)
        self.assertGreater(s["results"]["T_max"], 0.0)

    def test_refinement_shortens_the_sheet_elements_with_the_grains(self):
        # Each grain size's run: grains scaled by the factor, the sheet's elements too (its
        # discretisation belongs to the interface's micro model), its flexural rigidity
        # (bending stiffness per node x element length) and thickness held.
        pullout = """
kind = "pullout"
seed = 4
""" + SMALL_RUNOUT + """element_length = 0.016
bending_stiffness = 0.5
thickness = 0.001
[pull]
max_displacement = 0.004
history_points = 10
[refinement]
radius_factors = [1.0, 0.5]
[analytic]
soil_friction_deg = 30.0
"""
        out = self.dir / "refine"
        r = run("run", self.write(pullout, "po.toml"), "--out", str(out), "--quiet",
                "--threads", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads((out / "summary.json").read_text())["results"]
        self.assertEqual([g["radius_factor"] for g in res["groups"]], [1.0, 0.5])
        coarse_r, fine_r = (g["T_residual"]["mean"] for g in res["groups"])
        self.assertAlmostEqual(res["refinement"]["residual_change_finest_vs_first"],
                               fine_r / coarse_r - 1.0, places=12)
        runs = {}
        for d in sorted((out / "runs").iterdir()):
            sc = tomllib.loads((d / "scenario.toml").read_text())
            with open(d / "states" / "sheet_initial.csv") as f:
                nodes = sum(1 for _ in csv.DictReader(f))
            runs[sc["soil"]["radius"]] = (sc["sheet"], nodes)
        self.assertEqual(sorted(runs), [0.004, 0.008])
        coarse, fine = runs[0.008], runs[0.004]
        self.assertAlmostEqual(fine[0]["element_length"], 0.008, places=12)
        self.assertAlmostEqual(fine[0]["bending_stiffness"], 1.0, places=12)
        self.assertAlmostEqual(fine[0]["thickness"], coarse[0]["thickness"], places=12)
        self.assertAlmostEqual(coarse[0]["element_length"] * coarse[0]["bending_stiffness"],
                               fine[0]["element_length"] * fine[0]["bending_stiffness"],
                               places=12)
        # Twice the elements along the same sheet (a node on each end of each part).
        self.assertLessEqual(abs(fine[1] - 1 - 2 * (coarse[1] - 1)), 2)

    def test_sheet_flat_at_rest_round_a_rounded_edge(self):
        # An L whose trench edge is rounded: the sheet lies on the arc; flat at rest (the
        # default) its rest turns are zero once the fill holds it, and its moments are
        # k_b x turn; as laid, its rest turns keep the laid shape, a quarter turn in all.
        pullout = """
kind = "pullout"
[box]
length = 0.6
foundation = 0.12
[soil]
density = 2600.0
young = 2e7
friction_deg = 30.0
radius = 0.006
[anchor]
shape = "L"
runout_length = 0.3
cover = 0.06
trench_depth = 0.08
trench_width = 0.05
edge_radius = 0.03
[sheet]
interface_friction_deg = 20.0
bending_stiffness = 0.5
[pull]
max_displacement = 0.004
history_points = 10
[analytic]
soil_friction_deg = 30.0
[output]
plots = false
vtk = false
"""
        k_b, element = 0.5, 0.012
        sheets = {}
        for shape in ("flat", "as_laid"):
            out = self.dir / shape
            r = run("run", self.write(pullout, "L.toml"), "--out", str(out), "--quiet",
                    "--set", f'sheet.rest_shape="{shape}"')
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(out / "states" / "sheet_initial.csv") as f:
                sheets[shape] = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
        flat, laid = sheets["flat"], sheets["as_laid"]
        # Nodes: the run-out from the free end (4 radii out) to the arc, the arc, the trench
        # side below it, each cut into elements no longer than the default 2 radii.
        nodes = (1 + math.ceil((0.024 + 0.3 - 0.03) / element)
                 + math.ceil(0.03 * math.pi / 2 / element) + math.ceil((0.08 - 0.03) / element))
        self.assertEqual(len(flat), nodes)
        self.assertEqual(len(laid), nodes)
        self.assertTrue(all(n["rest_turn"] == 0.0 for n in flat))
        for n in flat:
            self.assertAlmostEqual(n["moment"], k_b * n["turn"], delta=1e-12)
        self.assertAlmostEqual(sum(n["rest_turn"] for n in laid), -math.pi / 2, delta=1e-9)
        for n in laid:
            self.assertAlmostEqual(n["moment"], k_b * (n["turn"] - n["rest_turn"]), delta=1e-12)


if __name__ == "__main__":
    GEODEM = os.path.abspath(sys.argv.pop(1))
    ROOT = Path(sys.argv.pop(1))
    unittest.main(verbosity=2)
