#!/usr/bin/env python3
"""An oedometer written in Python: a 2D scene of discs in a rigid box, loaded and unloaded by a
top plate whose servo is a Python callback (docs/python.md).

Stages: settle under gravity, then hold the plate at 10, 20, 40, 80, 160 kPa (loading) and 80,
40, 20 kPa (unloading); each stage ends when the plate stress is within 1 % of its target and
the unbalanced force ratio is below 0.01. Prints the void ratio at the end of each stage, the
compression index Cc (20 to 160 kPa) and the swelling index Cs (160 to 20 kPa), and plots void
ratio against log stress. usage: oedometer_servo.py [OUT_DIR] [SEED]
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

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else "runs/oedometer_servo")
SEED = int(sys.argv[2]) if len(sys.argv) > 2 else 1
WIDTH, HEIGHT = 0.1, 0.3

scene = geodem.scene({
    "kind": "scene", "dimension": 2, "seed": SEED,
    "time": {"step": "auto", "steps": 1},
    "physics": {"gravity": [0.0, -9.81], "local_damping": 0.3},
    "materials": [{"name": "sand", "young": 5e7, "friction": 0.5, "density": 2650.0}],
    "walls": [{"name": "floor", "normal": [0.0, 1.0], "area": WIDTH},
              {"name": "left", "point": [0.0, 0.0], "normal": [1.0, 0.0]},
              {"name": "right", "point": [WIDTH, 0.0], "normal": [-1.0, 0.0]},
              {"name": "top", "point": [0.0, HEIGHT], "normal": [0.0, -1.0], "area": WIDTH}],
    "clouds": [{"min": [0.0, 0.0], "max": [WIDTH, 0.9 * HEIGHT], "count": 800,
                "radius": 0.0015, "radius_fuzz": 0.25}],
})
solid = float(np.sum(math.pi * scene.radii ** 2))  # per metre of thickness


def plate_stress(s):
    return s.wall_force("top")[1] / WIDTH  # the grains push the plate up


def void_ratio(s):
    return (WIDTH * s.wall_point("top")[1] - solid) / solid


# Settle: the plate waits above the grains.
scene.run(until=1.0, every=500, callback=lambda s: s.unbalanced_force() > 1e-3 or s.time < 0.05)


def approach(s):
    """The plate comes down fast to half a millimetre above the highest grain."""
    top = float(np.max(s.positions[:, 1] + s.radii))
    far = s.wall_point("top")[1] > top + 0.0005
    s.set_wall_velocity("top", [0.0, -0.5 if far else 0.0])
    return far


scene.run(until=scene.time + 1.0, every=10, callback=approach)
target = 0.0


def servo(s):
    """The plate closes a fifth of its force error per callback (every 10 steps): a speed of
    0.02 x error / (contact stiffness x dt), as yade's stress controllers do; capped at 0.005
    m/s while it touches grains, 0.02 m/s while it touches none. A stage ends when the stress is
    within 1 % of its target and the sample is at rest."""
    error = target - plate_stress(s)
    k = s.wall_stiffness("top")
    v = max(-0.005, min(0.005, 0.02 * error * WIDTH / (k * s.dt))) if k > 0.0 else 0.02
    s.set_wall_velocity("top", [0.0, -v])
    return not (abs(error) < 0.01 * target and s.unbalanced_force() < 0.01)


stages = []
for kpa in (10, 20, 40, 80, 160, 80, 40, 20):
    target = kpa * 1e3
    scene.run(until=scene.time + 2.0, every=10, callback=servo)
    scene.set_wall_velocity("top", [0.0, 0.0])
    stages.append({"target_kPa": kpa, "stress_kPa": plate_stress(scene) / 1e3,
                   "void_ratio": void_ratio(scene), "time_s": scene.time,
                   "steps": scene.steps})
    print(f"{kpa:4d} kPa: stress {stages[-1]['stress_kPa']:.2f} kPa, void ratio "
          f"{stages[-1]['void_ratio']:.4f} (t = {scene.time:.3f} s)")

e = {(k, i): s["void_ratio"] for i, s in enumerate(stages) for k in [s["target_kPa"]]}
cc = (e[(20, 1)] - e[(160, 4)]) / math.log10(160 / 20)
cs = (e[(20, 7)] - e[(160, 4)]) / math.log10(160 / 20)
print(f"Cc = {cc:.4f}, Cs = {cs:.4f}")
OUT.mkdir(parents=True, exist_ok=True)
(OUT / "oedometer.json").write_text(json.dumps({"seed": SEED, "stages": stages, "Cc": cc,
                                                "Cs": cs}, indent=1))
fig, ax = plt.subplots(figsize=(5, 4))
ax.semilogx([s["stress_kPa"] for s in stages[:5]], [s["void_ratio"] for s in stages[:5]],
            "o-", label="loading")
ax.semilogx([s["stress_kPa"] for s in stages[4:]], [s["void_ratio"] for s in stages[4:]],
            "s--", label="unloading")
ax.set_xlabel("vertical stress (kPa)")
ax.set_ylabel("void ratio")
ax.set_title(f"Python-servo oedometer, 800 discs, seed {SEED}\nCc {cc:.4f}, Cs {cs:.4f}", fontsize=10)
ax.legend()
fig.tight_layout()
fig.savefig(OUT / "oedometer.png", dpi=100)
