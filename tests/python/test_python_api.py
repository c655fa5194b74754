"""The Python module is the same engine as the command line (docs/python.md).

Run by CTest (python.api) with PYTHONPATH pointing at the built module and GEODEM_BIN at the
command line: pytest tests/python.
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import geodem

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "cli"))
from small_scenarios import LAB_CHECKPOINT_TRIAXIAL  # noqa: E402

GEODEM = os.environ.get("GEODEM_BIN", "build/geodem")

SCENE = {
    "kind": "scene",
    "dimension": 2,
    "seed": 4,
    "time": {"step": "auto", "steps": 600},
    "physics": {"gravity": [0.0, -9.81], "local_damping": 0.2},
    "materials": [{"name": "sand", "young": 1e6, "friction": 0.5}],
    "walls": [{"name": "floor", "normal": [0.0, 1.0], "area": 0.2},
              {"name": "left", "point": [0.0, 0.0], "normal": [1.0, 0.0]},
              {"name": "right", "point": [0.2, 0.0], "normal": [-1.0, 0.0]}],
    "clouds": [{"min": [0.0, 0.0], "max": [0.2, 0.3], "count": 300, "radius": 0.004}],
    "output": {"history_every": 50, "vtk": False, "plots": False},
}


def run_cli(scenario_text, out, tmp_path):
    path = tmp_path / "scenario.toml"
    path.write_text(scenario_text)
    subprocess.run([GEODEM, "run", str(path), "--out", str(out), "--quiet"], check=True)
    return json.loads((out / "summary.json").read_text())


def test_triaxial_from_python_writes_the_cli_history(tmp_path):
    cli = tmp_path / "cli"
    run_cli(LAB_CHECKPOINT_TRIAXIAL, cli, tmp_path)
    summary = geodem.run(str(tmp_path / "scenario.toml"), out=str(tmp_path / "py"))
    assert summary["status"] == "completed" and summary["exit_code"] == 0
    for name in ("history.csv", "preparation.csv"):  # no wall-clock column: the whole files
        assert (cli / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name
    assert summary["results"] == json.loads((cli / "summary.json").read_text())["results"]


def test_oedometer_from_a_dict_gives_the_cli_results(tmp_path):
    """An element test given as a dict: the same run as its TOML file on the command line."""
    sample = LAB_CHECKPOINT_TRIAXIAL.split("[shear]")[0].replace('kind = "triaxial"',
                                                                  'kind = "oedometer"')
    text = sample + "[loading]\nstresses = [2e5, 1e5]\n[output]\nplots = false\nvtk = false\n"
    cli = tmp_path / "cli"
    run_cli(text, cli, tmp_path)
    import tomllib
    summary = geodem.run(tomllib.loads(text), out=str(tmp_path / "py"))
    assert summary["kind"] == "oedometer"
    assert (cli / "history.csv").read_bytes() == (tmp_path / "py" / "history.csv").read_bytes()
    r = summary["results"]
    assert r == json.loads((cli / "summary.json").read_text())["results"]
    assert len(r["points"]) == 3 and 0.0 < r["K0_at_largest_stress"] < 1.0


def toml_text(d, prefix=""):
    """A small TOML writer for the test's dicts (tables, arrays of tables, values)."""
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)
    lines, tables = [], []
    for k, v in d.items():
        if isinstance(v, dict):
            tables.append(f"[{prefix}{k}]\n" + toml_text(v, prefix + k + "."))
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                tables.append(f"[[{prefix}{k}]]\n" + toml_text(item, prefix + k + "."))
        else:
            lines.append(f"{k} = {value(v)}")
    return "\n".join(lines) + "\n" + "\n".join(tables)


def test_scene_stepped_from_python_ends_in_the_cli_state(tmp_path):
    cli = run_cli(toml_text(SCENE), tmp_path / "cli", tmp_path)["results"]
    scene = geodem.scene(SCENE)
    assert isinstance(scene, geodem.Scene2D) and scene.count == 300
    calls = []
    scene.run(steps=600, every=100, callback=lambda s: calls.append(s.steps))
    assert calls == [100, 200, 300, 400, 500, 600]
    assert scene.steps == cli["steps"] and scene.time == cli["time"]
    # The same bits: energies, extent of the grains, wall forces.
    assert scene.kinetic_energy() == cli["kinetic_energy"]
    x = scene.positions
    assert list(x.min(axis=0)) == cli["centres_min"]
    assert list(x.max(axis=0)) == cli["centres_max"]
    assert list(scene.wall_force("floor")) == cli["walls"]["floor"]["force"]


def test_callback_returning_false_stops_the_run():
    scene = geodem.scene(SCENE)
    scene.run(steps=1000, every=50, callback=lambda s: s.steps < 150)
    assert scene.steps == 150


def test_views_share_the_engine_memory():
    big = dict(SCENE, dimension=3, time={"step": "auto", "steps": 1})
    big["physics"] = {"gravity": [0.0, 0.0, -9.81]}
    big["walls"] = [{"name": "floor", "normal": [0.0, 0.0, 1.0]}]
    big["clouds"] = [{"min": [0.0, 0.0, 0.0], "max": [1.5, 1.5, 1.5], "count": 1_000_000,
                      "radius": 0.004}]
    scene = geodem.scene(big)
    assert scene.count == 1_000_000
    a, b = scene.positions, scene.positions
    assert a.shape == (1_000_000, 3) and a.dtype == np.float64
    assert not a.flags.owndata and not a.flags.writeable
    # Two reads are the same memory, the engine's: no copy was made.
    assert a.__array_interface__["data"][0] == b.__array_interface__["data"][0]
    assert np.shares_memory(a, b)
    v = scene.velocities
    scene.step(1)  # the engine writes into the memory the views read
    assert np.shares_memory(v, scene.velocities)
    assert v[:, 2].min() < 0.0


def test_walls_driven_from_python():
    scene = geodem.scene(SCENE)
    x0 = scene.wall_point("right")[0]
    scene.set_wall_velocity("right", [-0.01, 0.0])
    scene.step(100)
    assert scene.wall_point("right")[0] == pytest.approx(x0 - 0.01 * scene.time, rel=1e-9)
    with pytest.raises(KeyError, match="the walls are: floor, left, right"):
        scene.wall_force("roof")


def test_errors_are_python_exceptions():
    bad = dict(SCENE, materials=[{"name": "sand", "young": -1.0}])
    with pytest.raises(geodem.InputError, match="materials.0.young|young"):
        geodem.check(bad)
    with pytest.raises(geodem.InputError, match='unknown kind "scenery"'):
        geodem.check(dict(SCENE, kind="scenery"))
    assert geodem.check(SCENE).startswith('kind = "scene"')
    assert issubclass(geodem.InputError, ValueError)


def test_oedometer_example_gives_its_expected_figures(tmp_path):
    """examples/python/oedometer_servo.py, seed 1, against expected/oedometer_seed1.json."""
    root = Path(__file__).resolve().parent.parent.parent
    env = dict(os.environ, MPLBACKEND="Agg")
    subprocess.run([sys.executable, str(root / "examples/python/oedometer_servo.py"),
                    str(tmp_path), "1"], check=True, env=env, capture_output=True)
    got = json.loads((tmp_path / "oedometer.json").read_text())
    want = json.loads((root / "examples/python/expected/oedometer_seed1.json").read_text())
    for g, w in zip(got["stages"], want["stages"]):
        assert g["void_ratio"] == pytest.approx(w["void_ratio"], rel=1e-6)
        assert g["stress_kPa"] == pytest.approx(w["stress_kPa"], rel=1e-6)
    assert got["Cc"] == pytest.approx(want["Cc"], rel=1e-6)


def test_contact_arrays_of_two_grains_pressed_between_walls():
    """One contact of overlap d between two discs pressed by two walls: normal (0, 1), normal
    force kn d (kn = young per metre for two equal discs in 2D), no tangential force."""
    r, d, young = 0.01, 1e-5, 1e6
    y1 = r - d
    y2 = y1 + 2 * r - d
    scene = geodem.scene({
        "kind": "scene", "dimension": 2, "time": {"step": 1e-7, "steps": 1},
        "materials": [{"name": "m", "young": young, "friction": 0.5}],
        "walls": [{"name": "floor", "normal": [0.0, 1.0]},
                  {"name": "top", "point": [0.0, y2 + r - d], "normal": [0.0, -1.0]}],
        "particles": [{"position": [0.0, y1], "radius": r},
                      {"position": [0.0, y2], "radius": r}]})
    scene.step(1)
    c = scene.contacts()
    assert len(c["i"]) == 1 and not c["bonded"][0]
    assert c["overlap"][0] == pytest.approx(d, rel=1e-9)
    assert np.allclose(c["normal"][0], [0.0, 1.0] if c["i"][0] < c["j"][0] else [0.0, -1.0])
    assert c["normal_force"][0] == pytest.approx(young * d, rel=1e-9)
    assert np.abs(c["tangential_force"]).max() < 1e-12


def fabric(scene):
    """Fabric tensor <n n> of the contact normals, and its eigenvalues times D (1 if isotropic)."""
    n = scene.contacts()["normal"]
    f = n.T @ n / len(n)
    return f, np.linalg.eigvalsh(f) * scene.dimension


def test_fabric_isotropic_after_isotropic_compression_and_not_after_biaxial():
    """800 discs without gravity pushed together by four walls moving in at the same speed:
    the fabric is isotropic within 5 %. Then a biaxial test driven from Python: the top wall
    comes down at 0.01 m/s while a servo holds the side walls' force: after 10 % axial strain
    the contacts along the loading axis outnumber the others by more than 8 % (the isotropic
    packing: 2.6 %)."""
    w = 0.12
    scene = geodem.scene({
        "kind": "scene", "dimension": 2, "seed": 2, "time": {"step": "auto", "steps": 1},
        "physics": {"local_damping": 0.5},
        "materials": [{"name": "m", "young": 1e7, "friction": 0.3}],
        "walls": [{"name": "x0", "point": [0.0, 0.0], "normal": [1.0, 0.0]},
                  {"name": "x1", "point": [w, 0.0], "normal": [-1.0, 0.0]},
                  {"name": "y0", "point": [0.0, 0.0], "normal": [0.0, 1.0]},
                  {"name": "y1", "point": [0.0, w], "normal": [0.0, -1.0]}],
        "clouds": [{"min": [0.0, 0.0], "max": [w, w], "count": 800, "radius": 0.0015,
                    "radius_fuzz": 0.2}]})
    v = 0.05
    for name, vel in (("x0", [v, 0]), ("x1", [-v, 0]), ("y0", [0, v]), ("y1", [0, -v])):
        scene.set_wall_velocity(name, vel)
    # In until the walls press the packing (a mean wall force of 20 kN/m), then at rest.
    scene.run(until=1.0, every=20,
              callback=lambda s: np.mean([abs(s.wall_force(k)).max() for k in s.walls]) < 2e4)
    for name in scene.walls:
        scene.set_wall_velocity(name, [0.0, 0.0])
    scene.run(steps=20000, every=200, callback=lambda s: s.unbalanced_force() > 1e-3)
    f, iso = fabric(scene)
    assert np.abs(iso - 1.0).max() < 0.05, iso
    assert f[1, 1] / f[0, 0] < 1.05
    side = abs(scene.wall_force("x1")[0])
    top = scene.wall_point("y1")[1]
    height = top - scene.wall_point("y0")[1]

    def biaxial(s):
        for name, outward in (("x0", -1.0), ("x1", 1.0)):
            k = s.wall_stiffness(name)
            speed = 0.1 * (abs(s.wall_force(name)[0]) - side) / (k * s.dt) if k > 0 else -0.01
            s.set_wall_velocity(name, [outward * max(-0.01, min(0.01, speed)), 0.0])
        return s.wall_point("y1")[1] > top - 0.1 * height

    scene.set_wall_velocity("y1", [0.0, -0.01])
    scene.run(until=scene.time + 5.0, every=10, callback=biaxial)
    f, _ = fabric(scene)
    assert abs(scene.wall_force("x1")[0]) == pytest.approx(side, rel=0.02)  # the servo held
    assert f[1, 1] / f[0, 0] > 1.08, f
