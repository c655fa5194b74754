#!/usr/bin/env python3
"""The benchmark's scene (scene.toml) driven from Python: built by geodem.scene, stepped with
a callback every 100 steps that records what the command line's history row records (time,
kinetic energy, unbalanced force, coordination, floor force). usage: scene_from_python.py
SCENE.toml [THREADS]"""
import sys

import geodem

scene = geodem.scene(sys.argv[1])
scene.threads = int(sys.argv[2]) if len(sys.argv) > 2 else 1
rows = []


def record(s):
    rows.append((s.steps, s.time, s.dt, s.kinetic_energy(), s.unbalanced_force(),
                 s.coordination(), *s.wall_force("floor")))


scene.run(steps=3000, every=100, callback=record)
print(f"{len(rows)} rows, t = {scene.time:.6g} s, kinetic energy {rows[-1][3]:.6g} J")
