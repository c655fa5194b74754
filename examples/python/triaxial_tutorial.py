#!/usr/bin/env python3
"""yade's triaxial tutorial, written with geodem's Python API (docs/python.md).

As in yade's script: spheres in a box of six rigid walls are compressed isotropically to
sigma0 by wall servos with contact friction lowered (a dense sample), the friction is set
back to its true value, then the top and bottom walls close at a constant strain rate while
the four side walls hold sigma3 = sigma0. Here the servos are ten lines of Python called
every 10 steps, where yade has a TriaxialStressController. Prints the peak deviator stress,
the friction angle at the peak and the dilatancy, writes triaxial.json, and plots q and the
volumetric strain against the axial strain.

usage: triaxial_tutorial.py [OUT_DIR] [SEED]     (about a minute on one core)
"""
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import geodem  # noqa: E402

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else "runs/triaxial_tutorial")
SEED = int(sys.argv[2]) if len(sys.argv) > 2 else 1
SIGMA0 = 50e3      # confining stress (Pa)
FRICTION = 30.0    # contact friction angle (degrees), as yade's tutorial
RATE = 0.05        # axial strain rate (1/s)
L = 0.1            # initial box side (m)

walls = []
for axis, name in enumerate("xyz"):
    for side, sign in ((0, 1.0), (1, -1.0)):
        point, normal = [0.0] * 3, [0.0] * 3
        point[axis], normal[axis] = side * L, sign
        walls.append({"name": f"{name}{side}", "point": point, "normal": normal})
scene = geodem.scene({
    "kind": "scene", "dimension": 3, "seed": SEED,
    "time": {"step": "auto", "steps": 1, "safety": 0.5},
    "physics": {"local_damping": 0.2},  # yade's NewtonIntegrator(damping=0.2)
    "materials": [{"name": "sand", "young": 5e7, "kt_over_kn": 0.5, "density": 2600.0,
                   "friction_deg": FRICTION}],
    "walls": walls,
    "clouds": [{"min": [0, 0, 0], "max": [L, L, L], "count": 1000, "porosity": 0.8,
                "radius_fuzz": 0.3}],
})
solid = float(np.sum(4.0 / 3.0 * math.pi * scene.radii ** 3))


def box(s):
    """The sample's side lengths from the walls' positions."""
    return np.array([s.wall_point(f"{a}1")[k] - s.wall_point(f"{a}0")[k]
                     for k, a in enumerate("xyz")])


def stresses(s):
    """Normal stress on each axis (compression positive), mean of the two opposite walls."""
    side = box(s)
    area = np.array([side[1] * side[2], side[0] * side[2], side[0] * side[1]])
    return np.array([(s.wall_force(f"{a}1")[k] - s.wall_force(f"{a}0")[k]) / 2.0 / area[k]
                     for k, a in enumerate("xyz")])


EVERY = 10          # steps between calls of the Python servo
MAX_SPEED = 0.05    # m/s


def servo(s, axes, target):
    """yade's rule: each wall moves along its normal so that it would cancel half the force
    error (at its contacts' stiffness) by the next call, at most MAX_SPEED."""
    side = box(s)
    for k in axes:
        area = side[(k + 1) % 3] * side[(k + 2) % 3]
        for a, sign in ((f"{'xyz'[k]}0", 1.0), (f"{'xyz'[k]}1", -1.0)):
            force = -sign * s.wall_force(a)[k]  # the grains push the wall out: positive
            stiffness = max(s.wall_stiffness(a), 1e3)
            speed = 0.5 * (target * area - force) / stiffness / (EVERY * s.dt)
            v = [0.0, 0.0, 0.0]
            v[k] = sign * max(-MAX_SPEED, min(MAX_SPEED, speed))
            s.set_wall_velocity(a, v)


# 1. Isotropic compression, frictionless (a dense sample), until sigma0 holds at rest.
scene.set_friction(0.0)


def isotropic(s):
    servo(s, (0, 1, 2), SIGMA0)
    sig = stresses(s)
    return not (np.all(np.abs(sig / SIGMA0 - 1.0) < 0.01) and s.unbalanced_force() < 0.01)


scene.run(until=20.0, every=EVERY, callback=isotropic)
side0 = box(scene)
porosity0 = 1.0 - solid / side0.prod()
print(f"isotropic: {scene.steps} steps, porosity {porosity0:.4f}, stresses {stresses(scene)}")

# 2. The true friction, the same stress at rest again.
scene.set_friction(math.tan(math.radians(FRICTION)))
scene.run(until=scene.time + 20.0, every=EVERY, callback=isotropic)
side0 = box(scene)

# 3. Triaxial compression: z walls at the strain rate, side walls hold sigma3.
rows = []


def triaxial(s):
    v = RATE * box(s)[2] / 2.0
    s.set_wall_velocity("z0", [0.0, 0.0, v])
    s.set_wall_velocity("z1", [0.0, 0.0, -v])
    servo(s, (0, 1), SIGMA0)
    side = box(s)
    eps = 1.0 - side / side0  # strains, compression positive
    sig = stresses(s)
    rows.append({"axial_strain": eps[2], "volumetric_strain": eps.sum(),
                 "q": sig[2] - 0.5 * (sig[0] + sig[1]), "sigma3": 0.5 * (sig[0] + sig[1])})
    return eps[2] < 0.15


scene.run(until=scene.time + 0.15 / RATE * 1.2, every=EVERY, callback=triaxial)
q = np.array([r["q"] for r in rows])
ea = np.array([r["axial_strain"] for r in rows])
ev = np.array([r["volumetric_strain"] for r in rows])
peak = int(np.argmax(q))
sigma1 = q[peak] + SIGMA0
phi = math.degrees(math.asin((sigma1 - SIGMA0) / (sigma1 + SIGMA0)))
late = ea > 0.08
dilatancy = float(-np.polyfit(ea[late], ev[late], 1)[0]) if late.sum() > 3 else float("nan")
result = {"seed": SEED, "grains": scene.count, "porosity_after_compaction": porosity0,
          "peak_q": float(q[peak]), "axial_strain_at_peak": float(ea[peak]),
          "phi_peak_deg": phi, "dilatancy_after_8_percent": dilatancy,
          "steps": scene.steps}
print(json.dumps(result, indent=1))
OUT.mkdir(parents=True, exist_ok=True)
(OUT / "triaxial.json").write_text(json.dumps({"results": result, "history": rows}))
fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.0, 6.0), sharex=True)
a1.plot(ea * 100, q / 1e3)
a1.set_ylabel("deviator stress q (kPa)")
a1.set_title(f"Triaxial compression at {SIGMA0 / 1e3:.0f} kPa (seed {SEED})")
a2.plot(ea * 100, ev * 100)
a2.set_xlabel("axial strain (%)")
a2.set_ylabel("volumetric strain (%, compression +)")
fig.tight_layout()
fig.savefig(OUT / "triaxial.png", dpi=110)
