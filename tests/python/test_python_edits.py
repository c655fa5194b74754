"""Editing a scene from Python (friction, gravity, grains, walls), its fabric and force-chain
output, and checkpoints saved and loaded (docs/python.md)."""
import copy
import math

import numpy as np
import pytest

import geodem
from test_python_api import SCENE


def one_grain(dimension):
    """One grain on a floor, no gravity yet."""
    d = dimension
    return {
        "kind": "scene", "dimension": d,
        "time": {"step": 1e-5, "steps": 1},
        # The tangential dashpot damps the spring's vibration once the grain rolls.
        "materials": [{"name": "sand", "young": 1e7, "friction": 0.0, "restitution": 0.5,
                       "tangential_damping": True}],
        "walls": [{"name": "floor", "normal": [0.0] * (d - 1) + [1.0]}],
        "particles": [{"position": [0.0] * (d - 1) + [0.01], "radius": 0.01}],
        "output": {"vtk": False, "plots": False},
    }


@pytest.mark.parametrize("dimension", [2, 3])
def test_friction_set_from_python_stops_a_sliding_grain_as_in_closed_form(dimension):
    """A grain sliding on the floor at v0 under gravity g: frictionless, it keeps v0; with
    friction mu it slides until it rolls, at v0 / (1 + m r^2 / I) (2/3 v0 for a disc, 5/7 v0
    for a sphere), after t = (v0 - v_roll) / (mu g)."""
    scene = geodem.scene(one_grain(dimension))
    g, v0, mu = 9.81, 0.2, 0.3
    scene.set_gravity([0.0] * (dimension - 1) + [-g])
    scene.run(until=0.02)  # settles onto the floor (the dashpot damps the bounce)
    scene.add_grains(np.array([[0.5] + [0.0] * (dimension - 2) + [0.01]]), np.array([0.01]),
                     velocities=np.array([[v0] + [0.0] * (dimension - 1)]))
    scene.remove_grains(np.array([True, False]))  # keep the new grain only
    assert scene.count == 1
    scene.run(until=scene.time + 0.02)
    assert scene.velocities[0][0] == pytest.approx(v0, rel=1e-9)  # frictionless
    scene.set_friction(mu)
    ratio = 1.0 / (1.0 + (2.0 if dimension == 2 else 2.5))  # m r^2 / I = 2 (disc), 5/2 (sphere)
    v_roll = v0 * (1.0 - ratio)
    t_slip = (v0 - v_roll) / (mu * g)
    start = scene.time
    scene.run(until=start + 0.5 * t_slip, every=1)
    # Half way through the slip: v0 - mu g t (to within the bounce left from landing).
    assert scene.velocities[0][0] == pytest.approx(v0 - mu * g * (scene.time - start), rel=2e-3)
    scene.run(until=start + 2.0 * t_slip, every=10)
    assert scene.velocities[0][0] == pytest.approx(v_roll, rel=2e-3)


def settled(threads=1):
    scene = geodem.scene(SCENE)
    scene.threads = threads
    scene.step(600)
    return scene


def test_removed_grains_leave_and_the_others_keep_their_contacts():
    scene = settled()
    before = scene.contacts()
    ids = scene.ids
    x = scene.positions.copy()
    mask = x[:, 1] > np.median(x[:, 1])
    kept_ids = set(ids[~mask].tolist())
    removed = scene.remove_grains(mask)
    assert removed == int(mask.sum()) and scene.count == len(ids) - removed
    after = scene.contacts()
    new_ids = scene.ids

    def pairs(c, id_of):
        return {tuple(sorted((int(id_of[i]), int(id_of[j])))): tf for i, j, tf in
                zip(c["i"], c["j"], c["tangential_force"])}

    old = {p: tf for p, tf in pairs(before, ids).items() if set(p) <= kept_ids}
    new = pairs(after, new_ids)
    assert old.keys() == new.keys() and len(new) > 50
    for p in old:  # the springs are those of the same contacts, bit for bit
        assert np.array_equal(np.abs(old[p]), np.abs(new[p]))


def test_fabric_and_force_chain_frames(tmp_path):
    scene = settled()
    n = scene.contacts()["normal"]
    f = scene.fabric()
    assert np.allclose(f["tensor"], n.T @ n / len(n), rtol=0, atol=1e-14)
    eig = np.linalg.eigvalsh(f["tensor"])
    assert f["anisotropy"] == pytest.approx(2 * (eig[-1] - eig[0]), abs=1e-14)
    pvd = scene.write_vtk(str(tmp_path / "frames"))
    scene.step(10)
    scene.write_vtk(str(tmp_path / "frames"))
    text = open(pvd).read()
    for k in (0, 1):
        assert f"contacts_{k:06d}.vtp" in text and f"particles_{k:06d}.vtu" in text
    assert (tmp_path / "frames" / "vtk" / "contacts_000001.vtp").stat().st_size > 1000


def test_displacements_since_a_reference():
    scene = geodem.scene(SCENE)
    scene.step(100)
    scene.set_reference()
    start = dict(zip(scene.ids.tolist(), scene.positions.copy()))
    scene.step(300)  # the grains are renumbered on the way
    u = scene.displacements()
    for k, i in enumerate(scene.ids.tolist()):
        assert np.array_equal(u[k], scene.positions[k] - start[i])
    scene.add_grains(np.array([[0.1, 0.35]]), np.array([0.004]))
    assert np.all(np.isnan(scene.displacements()[-1]))


def test_saved_and_loaded_scene_continues_bit_for_bit(tmp_path):
    scene = settled()
    scene.remove_wall("right")  # the saved state has its own wall list
    scene.set_friction(0.2)
    scene.save(str(tmp_path / "a.ckpt"))
    scene.step(300)
    again = geodem.load(str(tmp_path / "a.ckpt"))
    assert again.walls == ["floor", "left"]
    again.step(300)
    assert again.steps == scene.steps and again.time == scene.time
    assert np.array_equal(again.positions, scene.positions)
    assert np.array_equal(again.velocities, scene.velocities)
    with pytest.raises(geodem.InputError, match="checkpoint"):
        (tmp_path / "bad.ckpt").write_bytes(b"not a checkpoint")
        geodem.load(str(tmp_path / "bad.ckpt"))


def test_edit_errors_are_python_exceptions():
    scene = geodem.scene(copy.deepcopy(SCENE))
    with pytest.raises(ValueError, match="mask"):
        scene.remove_grains(np.zeros(3, dtype=bool))
    with pytest.raises(ValueError, match="shape"):
        scene.add_grains(np.zeros((2, 3)), np.ones(2))
    with pytest.raises(KeyError, match="no material"):
        scene.add_grains(np.zeros((1, 2)), np.ones(1), material="clay")
    with pytest.raises(ValueError):
        scene.set_friction(-1.0)
    assert math.isfinite(scene.dt)
