"""A world built from Python: an empty scene filled with walls, grains, clumps, clouds, chains
and bonds, each given with the keys of its TOML table (docs/python.md)."""
import copy
import math

import numpy as np
import pytest

import geodem

G = 9.81
RHO = 2650.0


def empty(dimension=2, **physics):
    """A scene with a material and nothing else: no walls, no grains."""
    return {
        "dimension": dimension,
        "materials": [{"name": "sand", "young": 1e7, "friction": 0.5, "restitution": 0.3,
                       "density": RHO, "normal_cohesion": 1e5, "shear_cohesion": 1e5}],
        "physics": {"gravity": [0.0] * (dimension - 1) + [-G], **physics},
        "output": {"vtk": False, "plots": False},
    }


def test_a_grain_added_to_an_empty_world_falls_and_rests_with_its_weight_on_the_floor():
    """Free fall: the leapfrog's drop after n steps from rest is g/2 (t^2 + t dt), t = n dt
    (g t^2 / 2 to first order in dt); at rest the floor carries m g, m = rho pi r^2 per
    metre (a disc)."""
    scene = geodem.scene(empty())
    assert scene.count == 0 and scene.walls == []
    assert scene.add_walls({"name": "floor", "normal": [0.0, 1.0]}) == ["floor"]
    r, y0 = 0.01, 0.05
    scene.add_grains(np.array([[0.0, y0]]), np.array([r]))
    assert scene.masses[0] == pytest.approx(RHO * math.pi * r * r, rel=1e-12)
    assert list(scene.clump_ids) == [-1]
    assert scene.spins.shape == (1,) and not scene.spins.flags.owndata
    scene.run(until=0.05, every=1)  # falls 12 mm of the 40 it has
    t, dt = scene.time, scene.dt
    assert y0 - scene.positions[0][1] == pytest.approx(0.5 * G * (t * t + t * dt), rel=1e-9)
    scene.run(until=2.0, every=1000)
    weight = RHO * math.pi * r * r * G
    assert scene.kinetic_energy() < 1e-12
    assert scene.wall_force("floor")[1] == pytest.approx(-weight, rel=1e-6)


def test_a_clump_added_from_python_falls_rigid_and_rests_with_its_weight():
    """The built-in "pair" (two touching discs of radius `scale`): in free fall its members
    keep their distance 2 r and their centre falls g t^2 / 2; at rest the floor carries
    2 rho pi r^2 g."""
    scene = geodem.scene(empty())
    scene.add_walls([{"name": "floor", "normal": [0.0, 1.0]},
                     {"name": "left", "point": [-0.1, 0.0], "normal": [1.0, 0.0]}])
    r, y0 = 0.01, 0.08
    assert scene.add_clumps({"template": "pair", "position": [0.0, y0], "scale": r,
                             "angle_deg": 30.0}) == 1
    assert scene.count == 2
    start = 0.5 * (scene.positions[0] + scene.positions[1])  # the clump's centre of mass
    scene.run(until=0.05, every=10)
    x = scene.positions
    assert np.linalg.norm(x[1] - x[0]) == pytest.approx(2.0 * r, rel=1e-12)
    ids = scene.clump_ids
    assert ids[0] == ids[1] >= 0
    assert np.all(scene.spins == 0.0)  # a free fall turns nothing
    centre = 0.5 * (x[0] + x[1])
    t, dt = scene.time, scene.dt
    assert centre[0] == start[0]
    assert start[1] - centre[1] == pytest.approx(0.5 * G * (t * t + t * dt), rel=1e-9)
    scene.run(until=3.0, every=1000)
    assert scene.wall_force("floor")[1] == pytest.approx(-2.0 * RHO * math.pi * r * r * G, rel=1e-6)


def full_scene():
    """Walls, a chain held at both ends, a cloud and bonds, given in the scenario."""
    s = empty()
    s["seed"] = 5
    s["walls"] = [{"name": "box", "type": "polyline", "closed": True,
                   "points": [[0.0, 0.0], [0.3, 0.0], [0.3, 0.3], [0.0, 0.3]]}]
    s["chains"] = [{"name": "sheet", "points": [[0.02, 0.05], [0.28, 0.05]],
                    "element_length": 0.02, "held": [0, -1]}]
    s["clouds"] = [{"min": [0.01, 0.07], "max": [0.29, 0.29], "count": 120, "radius": 0.008,
                    "radius_fuzz": 0.2}]
    s["bonds"] = {"create": "initial", "gap_tolerance": 0.5}
    return s


def test_a_world_built_from_python_steps_as_the_same_world_given_in_the_scenario():
    """An empty scene filled by add_walls, add_chain, add_cloud and create_bonds ends, after
    400 steps, in the same state to the bit as the scene whose scenario gives them."""
    given = geodem.scene(full_scene())
    built_from = {k: v for k, v in full_scene().items()
                  if k not in ("walls", "chains", "clouds", "bonds")}
    built = geodem.scene(built_from)
    spec = full_scene()
    assert len(built.add_walls(spec["walls"])) == 4  # one per side of the closed polyline
    assert built.add_chain(spec["chains"][0]) == ["sheet"]
    assert built.add_cloud(spec["clouds"][0]) == 120
    assert built.create_bonds(0.5) > 0
    assert built.walls == given.walls and built.count == given.count
    for scene in (given, built):
        scene.step(400)
    assert np.array_equal(built.positions, given.positions)
    assert np.array_equal(built.velocities, given.velocities)
    assert built.kinetic_energy() == given.kinetic_energy()
    assert np.array_equal(built.contacts()["bonded"], given.contacts()["bonded"])


def test_clouds_added_from_python_clear_the_grains_there():
    scene = geodem.scene(empty())
    scene.add_walls({"name": "floor", "normal": [0.0, 1.0]})
    box = {"min": [0.0, 0.0], "max": [0.3, 0.3], "count": 40, "radius": 0.008}
    assert scene.add_cloud(box) == 40
    assert scene.add_cloud(box) == 40
    x, r = scene.positions, scene.radii
    gap = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2) - (r[:, None] + r[None, :])
    np.fill_diagonal(gap, 1.0)
    assert gap.min() >= 0.0


def test_bad_parts_raise_input_errors_naming_the_key():
    scene = geodem.scene(empty())
    scene.add_walls({"name": "floor", "normal": [0.0, 1.0]})
    with pytest.raises(geodem.InputError, match="already"):
        scene.add_walls({"name": "floor", "normal": [0.0, 1.0]})
    with pytest.raises(geodem.InputError, match="walls.*velocty"):
        scene.add_walls({"name": "top", "normal": [0.0, -1.0], "velocty": [0.0, 0.0]})
    with pytest.raises(geodem.InputError, match="clumps.*template"):
        scene.add_clumps({"template": "triangle"})
    with pytest.raises(geodem.InputError, match="chains.*points"):
        scene.add_chain({"points": [[0.0, 0.0], [0.0, 0.0]]})
    with pytest.raises(geodem.InputError, match="material"):
        scene.add_cloud({"min": [0, 0], "max": [1, 1], "count": 3, "radius": 0.1,
                         "material": "clay"})
    plain = copy.deepcopy(empty())
    del plain["materials"][0]["normal_cohesion"], plain["materials"][0]["shear_cohesion"]
    with pytest.raises(geodem.InputError, match="cohesive"):
        geodem.scene(plain).create_bonds()
    assert scene.walls == ["floor"]  # nothing added by the calls that failed


def test_grains_added_on_top_of_others_are_an_input_error():
    """An overlap the step would stop at (half the smaller radius by default) is refused at
    the call, naming both grains; nothing is added."""
    scene = geodem.scene(empty())
    scene.add_grains(np.array([[0.0, 0.0]]), np.array([0.01]))
    with pytest.raises(geodem.InputError, match=r"positions\[1\].*overlaps.*id 0"):
        scene.add_grains(np.array([[0.5, 0.0], [0.005, 0.0]]), np.array([0.01, 0.01]))
    assert scene.count == 1
    assert scene.add_grains(np.array([[0.019, 0.0]]), np.array([0.01])) == 1  # 5 %: a contact
