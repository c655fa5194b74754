"""Scenes in stages ([[stages]]), the final packing (particles.csv), and the contact
network written as VTK lines (force chains) with the fabric columns.

Run by CTest: python3 test_stages.py GEODEM_BINARY
"""
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET
from pathlib import Path

from small_scenarios import LAB_CHECKPOINT_TRIAXIAL, SMALL_STAGED

GEODEM = None


def run(*args):
    return subprocess.run([GEODEM, *args], capture_output=True, text=True, timeout=300)


def history(folder):
    with open(Path(folder) / "history.csv") as f:
        return list(csv.DictReader(f))


def comparable(folder):
    """The history without its wall-clock column, and the results without the checkpoint's
    path: what a resumed run must reproduce bit for bit."""
    rows = [{k: v for k, v in r.items() if k != "wall_s"} for r in history(folder)]
    results = json.loads((Path(folder) / "summary.json").read_text())["results"]
    results.pop("checkpoint", None)
    return rows, json.dumps(results, sort_keys=True)


def read_vtk(path):
    """A VTK XML file with raw appended data: its XML (checked well-formed by parsing it with
    the binary section cut out) and its arrays by name, as lists of numbers."""
    raw = Path(path).read_bytes()
    head, _, rest = raw.partition(b'<AppendedData encoding="raw">\n_')
    blob, _, tail = rest.rpartition(b"\n</AppendedData>")
    root = ET.fromstring(head + b'<AppendedData encoding="raw"/>' + tail)  # raises if malformed
    arrays = {}
    for a in root.iter("DataArray"):
        offset = int(a.get("offset"))
        (size,) = struct.unpack_from("<Q", blob, offset)
        fmt = {"Float64": "d", "Int64": "q", "UInt32": "I", "Int32": "i", "UInt8": "B"}[a.get("type")]
        width = struct.calcsize(fmt)
        arrays[a.get("Name")] = list(struct.unpack_from(f"<{size // width}{fmt}", blob, offset + 8))
    return root, arrays


class StagedSceneTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def run_scene(self, text, name="s"):
        scenario = self.dir / f"{name}.toml"
        scenario.write_text(text)
        out = self.dir / name
        r = run("run", str(scenario), "--out", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        return out, json.loads((out / "summary.json").read_text())["results"]

    def resume_copy(self, ref, cp, name):
        """A copy of the finished run `ref` as if killed after checkpoint `cp` (later
        checkpoints removed), resumed with scenario NAME.toml; returns its folder."""
        out = self.dir / (f"{name}_from_" + cp.stem)
        shutil.copytree(ref, out)
        for later in (out / "checkpoint").glob("checkpoint_*.bin"):
            if later.name > cp.name:
                later.unlink()
        r = run("run", str(self.dir / f"{name}.toml"), "--resume", str(out), "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        return out

    def test_servo_stage_holds_its_target_and_the_walls_carry_the_weight(self):
        out, res = self.run_scene(SMALL_STAGED)
        stages = res["stages"]
        self.assertEqual([s["name"] for s in stages], ["settle", "drop", "excavate", "load"])
        for s in stages:
            self.assertEqual(s["stop_reason"], "at rest (stop criteria met)", s["name"])
        # Closed form of the servo stage: the plate's stress is its target (within 1 %).
        servo = stages[3]["servos"][0]
        self.assertEqual(servo["wall"], "plate")
        self.assertLess(abs(servo["stress"] / 10e3 - 1.0), 0.01, servo)
        # At rest the walls carry the grains' weight: the vertical forces the grains exert
        # on the walls sum to the weight (within 1 % of the plate's load).
        walls = res["walls"]
        self.assertNotIn("gate", walls)
        fy = sum(w["force"][1] for w in walls.values())
        plate_load = servo["stress"] * 0.1
        self.assertLess(abs(fy + res["total_weight"]), 0.01 * plate_load,
                        (fy, res["total_weight"]))
        # The excavation removed grains; the stage column numbers the stages; a wall's
        # columns are empty (NaN) while it is absent.
        rows = history(out)
        self.assertEqual(sorted({r["stage"] for r in rows}), ["1", "2", "3", "4"])
        for r in rows:
            gate_there = r["stage"] == "1"
            self.assertEqual(math.isnan(float(r["wall_gate_fy"])), not gate_there, r["step"])
            self.assertEqual(math.isnan(float(r["wall_plate_stress"])), r["stage"] != "4")
        self.assertLess(res["particles"], 300)
        self.assertTrue((out / "particles.csv").is_file())

    def test_resumed_from_a_checkpoint_in_each_stage_bitwise(self):
        text = SMALL_STAGED + "\n[checkpoint]\nevery_steps = 400\nkeep = 1000\n"
        ref, _ = self.run_scene(text, "ref")
        expected = comparable(ref)
        stage_of = {int(float(r["step"])): r["stage"] for r in history(ref)}
        checkpoints = sorted((ref / "checkpoint").glob("checkpoint_*.bin"))
        # The first checkpoint of each stage, and the last one (the finished run).
        chosen, seen = [checkpoints[-1]], set()
        for cp in checkpoints:
            step = int(cp.stem.split("_")[1])
            stage = stage_of.get(min((s for s in stage_of if s >= step), default=max(stage_of)))
            if stage not in seen:
                seen.add(stage)
                chosen.append(cp)
        self.assertEqual(len(seen), 4)
        for cp in chosen:
            out = self.resume_copy(ref, cp, "ref")
            got = comparable(out)
            self.assertEqual(got[1], expected[1], cp.name)
            self.assertEqual(got[0], expected[0], cp.name)
            shutil.rmtree(out)

    def test_final_packing_reads_back(self):
        first, res = self.run_scene(SMALL_STAGED, "first")
        table = (first / "particles.csv").read_text()
        self.assertIn("# columns: id x y radius vx vy material", table)
        # A second scene starts from the packing: its columns come from the file's header.
        second = f"""
kind = "scene"
dimension = 2
[time]
steps = 1
step = 1e-7
[[materials]]
name = "sand"
density = 2650.0
young = 2e6
[[particle_files]]
file = "{first / 'particles.csv'}"
[output]
vtk = false
plots = false
"""
        _, res2 = self.run_scene(second, "second")
        self.assertEqual(res2["particles"], res["particles"])
        for key in ("centres_min", "centres_max"):
            for a, b in zip(res2[key], res[key]):
                self.assertLess(abs(a - b), 1e-6, key)

    def test_force_chains_and_fabric(self):
        text = SMALL_STAGED.replace("vtk = false", "vtk = true\nvtk_contacts = true")
        out, res = self.run_scene(text)
        pvd = (out / "vtk" / "particles.pvd").read_text()
        frames = sorted((out / "vtk").glob("contacts_*.vtp"))
        self.assertGreaterEqual(len(frames), 2)
        for f in frames:
            self.assertIn(f.name, pvd)
        ET.fromstring(pvd)
        root, a = read_vtk(frames[-1])
        piece = root.find("PolyData/Piece")
        lines, points = int(piece.get("NumberOfLines")), int(piece.get("NumberOfPoints"))
        # The last frame is the end state: as many lines as grain-grain contacts in the
        # last history row, one point per grain.
        last = history(out)[-1]
        self.assertEqual(lines, int(float(last["contacts"])))
        self.assertEqual(points, res["particles"])
        conn, xyz = a["connectivity"], a["Points"]
        self.assertEqual(len(conn), 2 * lines)
        for k in range(lines):
            i, j = conn[2 * k], conn[2 * k + 1]
            d = [xyz[3 * j + c] - xyz[3 * i + c] for c in range(3)]
            norm = math.sqrt(sum(x * x for x in d))
            for c in range(3):  # the normal runs from the line's first grain to its second
                self.assertAlmostEqual(a["normal"][3 * k + c], d[c] / norm, places=12)
            self.assertGreater(a["normal_force"][k], 0.0)
            ft = math.sqrt(sum(a["tangential_force"][3 * k + c] ** 2 for c in range(3)))
            self.assertAlmostEqual(a["force"][k], math.hypot(a["normal_force"][k], ft), places=9)
            # The tangential force lies in the contact's tangent plane.
            tn = sum(a["tangential_force"][3 * k + c] * a["normal"][3 * k + c] for c in range(3))
            self.assertLess(abs(tn), 1e-9 * (ft + 1e-30) + 1e-15)
        # Displacements since the start in the grains' frames: the last frame's are the
        # positions minus the first frame's, grain by grain (by id).
        _, first = read_vtk(out / "vtk" / "particles_000000.vtu")
        _, final = read_vtk(sorted((out / "vtk").glob("particles_*.vtu"))[-1])
        start = {i: first["Points"][3 * k:3 * k + 3] for k, i in enumerate(first["id"])}
        for k, i in enumerate(final["id"]):
            for c in range(2):
                self.assertEqual(final["displacement"][3 * k + c],
                                 final["Points"][3 * k + c] - start[i][c])
        # The fabric columns: trace 1, and the summary's tensor is the last row's.
        self.assertAlmostEqual(float(last["fabric_xx"]) + float(last["fabric_yy"]), 1.0, places=12)
        fab = res["fabric"]
        self.assertEqual(fab["tensor"][0][0], float(last["fabric_xx"]))
        lam = (fab["tensor"][0][0] + fab["tensor"][1][1]) / 2
        dev = math.hypot((fab["tensor"][0][0] - fab["tensor"][1][1]) / 2, fab["tensor"][0][1])
        self.assertAlmostEqual(fab["anisotropy"], 2 * 2 * dev, places=12)
        self.assertAlmostEqual(lam, 0.5, places=12)

    def test_a_scene_starts_from_another_runs_checkpoint(self):
        # Run A settles and drops the deposit; run B starts from A's last checkpoint and
        # excavates and loads it (the second half of the staged example).
        head, rest = SMALL_STAGED.split('[[stages]]\nname = "excavate"')
        tail = rest[rest.index("[output]"):]
        a_text = head + tail + "\n[checkpoint]\nevery_steps = 1000000\n"
        a, res_a = self.run_scene(a_text, "a")
        materials = SMALL_STAGED[SMALL_STAGED.index("[[materials]]"):
                                 SMALL_STAGED.index("[[walls]]")]
        b_text = ('kind = "scene"\ndimension = 2\n[time]\nstep = "auto"\nsafety = 0.5\n'
                  "[physics]\nlocal_damping = 0.3\ngravity = [0.0, -9.81]\n" + materials +
                  f'[start]\ncheckpoint = "{a}"\n' + '[[stages]]\nname = "restart"\nsteps = 1\n'
                  + '[[stages]]\nname = "excavate"' + rest +
                  "\n[checkpoint]\nevery_steps = 400\nkeep = 1000\n")
        b, res_b = self.run_scene(b_text, "b")
        self.assertEqual([s["name"] for s in res_b["stages"]], ["restart", "excavate", "load"])
        servo = res_b["stages"][2]["servos"][0]
        self.assertLess(abs(servo["stress"] / 10e3 - 1.0), 0.01, servo)
        # B's first record (one step of a stage that changes nothing) is A's end state: the
        # same grains and contacts.
        first = history(b)[0]
        last_a = history(a)[-1]
        self.assertEqual(first["contacts"], last_a["contacts"])
        self.assertEqual(sorted(res_b["walls"]), ["floor", "left", "plate", "right"])
        self.assertLess(res_b["particles"], res_a["particles"])
        self.assertEqual(float(first["time"]), float(first["dt"]))  # time starts at zero
        # B resumes bit for bit from a checkpoint in its servo stage (A's file is read again).
        expected = comparable(b)
        checkpoints = sorted((b / "checkpoint").glob("checkpoint_*.bin"))
        cp = checkpoints[len(checkpoints) * 3 // 4]
        self.assertEqual(comparable(self.resume_copy(b, cp, "b")), expected)
        # A checkpoint that does not fit is an input error naming [start].
        bad = b_text.replace('name = "sand"', 'name = "clay"')
        p = self.dir / "bad.toml"
        p.write_text(bad.replace("[[stages.add_walls]]", "[[stages.add_walls]]\nmaterial = \"clay\""))
        r = run("run", str(p), "--out", str(self.dir / "bad"), "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("start.checkpoint", r.stderr)
        self.assertIn("material", r.stderr)

    def test_lab_kinds_write_force_chains_too(self):
        text = LAB_CHECKPOINT_TRIAXIAL.replace("[output]\n", "[output]\nvtk_contacts = true\n")
        out, _ = self.run_scene(text, "triaxial")
        frames = sorted((out / "vtk").glob("contacts_*.vtp"))
        particles = sorted((out / "vtk").glob("particles_*.vtu"))
        self.assertEqual(len(frames), len(particles))
        self.assertGreater(len(frames), 1)
        pvd = (out / "vtk" / "particles.pvd").read_text()
        root, a = read_vtk(frames[-1])
        lines = int(root.find("PolyData/Piece").get("NumberOfLines"))
        self.assertGreater(lines, 50)
        self.assertEqual(len(a["force"]), lines)
        for f in frames:
            self.assertIn(f.name, pvd)

    def test_bad_stages_name_the_key(self):
        cases = [
            (SMALL_STAGED.replace('remove_walls = ["gate"]', 'remove_walls = ["door"]'),
             "stages.1.remove_walls", "no wall 'door'"),
            (SMALL_STAGED.replace("area = 0.1\n", ""), "stages.3.walls.0.servo_stress",
             "plane wall with an 'area'"),
            (SMALL_STAGED.replace("name = \"drop\"\n", "name = \"drop\"\nsteps = 0\n")
             .replace("duration = 1.0\n[stages.stop]\nunbalanced_below = 2e-3\nmin_time = 0.1",
                      "[stages.stop]\nunbalanced_below = 2e-3\nmin_time = 0.1", 1),
             "stages.1.duration", "give the stage's 'duration'"),
            (SMALL_STAGED.replace("[time]\n", "[time]\nduration = 1.0\n"), "time.duration",
             "each stage its own"),
        ]
        for text, key, words in cases:
            p = self.dir / "bad.toml"
            p.write_text(text)
            r = run("check", str(p))
            self.assertEqual(r.returncode, 2, (key, r.stderr))
            self.assertIn(key, r.stderr)
            self.assertIn(words, r.stderr)


if __name__ == "__main__":
    GEODEM = os.path.abspath(sys.argv.pop(1))
    unittest.main(verbosity=2)
