"""The engine's plate servo driven from Python (docs/python.md): a plate held at its target
stress, against the closed form of the vertical equilibrium."""
import math

import numpy as np
import pytest

import geodem

G = 9.81
RHO = 2650.0
WIDTH = 0.2


def box_of_discs():
    """150 discs in a box of smooth walls (frictionless: the floor carries all the weight)."""
    return {
        "dimension": 2, "seed": 3,
        "physics": {"gravity": [0.0, -G], "local_damping": 0.3},
        "materials": [{"name": "sand", "young": 1e7, "friction": 0.5, "density": RHO},
                      {"name": "smooth", "young": 1e7, "friction": 0.0}],
        "walls": [
            {"name": "floor", "normal": [0.0, 1.0], "material": "smooth", "area": WIDTH},
            {"name": "left", "normal": [1.0, 0.0], "material": "smooth"},
            {"name": "right", "point": [WIDTH, 0.0], "normal": [-1.0, 0.0], "material": "smooth"},
            {"name": "plate", "point": [0.0, 0.15], "normal": [0.0, -1.0], "material": "smooth",
             "area": WIDTH},
        ],
        "clouds": [{"min": [0.0, 0.0], "max": [WIDTH, 0.14], "count": 150, "radius": 0.004,
                    "radius_fuzz": 0.2}],
    }


def test_a_servo_set_from_python_holds_the_plate_at_its_target():
    """At rest the plate holds its target within 1 %, and the floor carries the plate's load
    plus the grains' weight, rho g sum(pi r^2) (frictionless side walls), within 1 %."""
    scene = geodem.scene(box_of_discs())
    target = 10e3
    scene.set_servo("plate", stress=target, max_speed=0.2)

    def at_rest(s):
        ok = abs(s.wall_stress("plate") / target - 1.0) < 1e-3 and s.unbalanced_force() < 1e-3
        return not ok and s.time < 4.0

    scene.run(every=500, callback=at_rest)
    assert scene.time < 4.0, "the plate did not settle"
    assert scene.wall_stress("plate") == pytest.approx(target, rel=1e-2)
    weight = RHO * G * math.pi * float(np.sum(scene.radii ** 2))
    plate = scene.wall_force("plate")[1]  # the grains push the plate up
    assert scene.wall_force("floor")[1] == pytest.approx(-(plate + weight), rel=1e-2)
    assert plate == pytest.approx(target * WIDTH, rel=1e-2)

    # Removing the servo stops the plate; removing the wall drops its servo with it.
    scene.remove_servo("plate")
    y = scene.wall_point("plate")[1]
    scene.step(200)
    assert scene.wall_point("plate")[1] == y
    scene.set_servo("plate", stress=2 * target, max_speed=0.05)
    scene.remove_wall("plate")
    scene.step(10)
    assert "plate" not in scene.walls


def test_a_servo_needs_an_area():
    scene = geodem.scene(box_of_discs())
    with pytest.raises(geodem.InputError, match="area"):
        scene.set_servo("left", stress=1e3, max_speed=0.01)
    with pytest.raises(KeyError):
        scene.set_servo("roof", stress=1e3, max_speed=0.01)


def test_wall_contacts_add_up_to_the_wall_forces_at_rest():
    """At rest (no dashpot left), the elastic forces of each wall's contacts, fn n + ft on
    the wall, add up to the force the step sums on it."""
    scene = geodem.scene(box_of_discs())
    scene.set_servo("plate", stress=10e3, max_speed=0.2)
    scene.run(until=1.0, every=1000)
    c = scene.wall_contacts()
    assert len(c["grain"]) > 0 and np.all(c["overlap"] > 0.0)
    total = c["normal_force"][:, None] * c["normal"] + c["tangential_force"]
    for k, name in enumerate(scene.walls):
        mine = c["wall"] == k
        assert total[mine].sum(axis=0) == pytest.approx(scene.wall_force(name), rel=1e-6,
                                                        abs=1e-9)
    floor = c["wall"] == scene.walls.index("floor")
    assert np.allclose(c["normal"][floor], [0.0, -1.0])
