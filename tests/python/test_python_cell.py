"""The periodic cell from Python (docs/python.md): grains carried by an imposed simple shear
on the affine profile, and the cell servo holding an isotropic stress target."""
import numpy as np
import pytest

import geodem

SIDE = 0.2


def discs(count, radius, friction=0.5):
    """Discs at random in [0, SIDE]^2, no walls, no gravity."""
    return {
        "dimension": 2, "seed": 5,
        "physics": {"local_damping": 0.3},
        "materials": [{"name": "sand", "young": 1e7, "friction": friction}],
        "clouds": [{"min": [0.0, 0.0], "max": [SIDE, SIDE], "count": count, "radius": radius,
                    "radius_fuzz": 0.2}],
    }


def test_simple_shear_carries_grains_on_the_affine_profile():
    """Grains without contacts follow x = x0 + rate y0 t (modulo the cell), to 1e-12 of the
    cell, and the cell leans by rate t."""
    scene = geodem.scene(discs(40, 0.003))
    scene.set_periodic([SIDE, SIDE])
    rate = 20.0
    scene.set_velocity_gradient(np.array([[0.0, rate], [0.0, 0.0]]))
    x0 = {i: p.copy() for i, p in zip(scene.ids, scene.positions)}
    t0 = scene.time
    scene.step(300)
    t = scene.time - t0
    h = scene.cell
    assert h[0, 1] / h[1, 1] == pytest.approx(rate * t, rel=1e-12)
    worst = 0.0
    for i, p in zip(scene.ids, scene.positions):
        want = x0[i] + np.array([rate * x0[i][1] * t, 0.0])
        d = p - want
        d -= h @ np.round(np.linalg.solve(h, d))  # the same grain, or its image
        worst = max(worst, float(np.linalg.norm(d)))
    assert worst < 1e-12 * SIDE


def test_cell_servo_holds_an_isotropic_stress():
    """A loose cloud of 400 discs compressed by the cell servo to 20 kPa: the cell's stress
    holds the target on both axes within 1 % (the servo drives the normal components only: a
    small packing may lock in a shear stress of a few per cent, which it leaves)."""
    scene = geodem.scene(discs(400, 0.004, friction=0.3))
    scene.set_periodic([SIDE, SIDE])
    target = 2e4
    scene.set_cell_servo([{"stress": target}, {"stress": target}], max_strain_rate=2.0)

    def settling(s):
        sigma = s.cell_stress()
        ok = max(abs(sigma[0, 0] / target - 1.0), abs(sigma[1, 1] / target - 1.0)) < 1e-3
        return not ok and s.time < 5.0

    scene.run(every=200, callback=settling)
    assert scene.time < 5.0, "the cell did not reach its target"
    worst = 0.0
    for _ in range(20):
        scene.step(50)
        sigma = scene.cell_stress()
        worst = max(worst, abs(sigma[0, 0] / target - 1.0), abs(sigma[1, 1] / target - 1.0))
    assert worst < 1e-2
    assert scene.cell[0, 0] < SIDE  # it closed in
    scene.remove_cell_servo()
    with pytest.raises(ValueError):
        scene.set_cell_servo([{"stress": 1.0}], max_strain_rate=1.0)  # one dict per axis
