# -*- coding: utf-8 -*-
# Benchmark B1 "triax3d", yade side: the triaxial test of yade's triax tutorial
# (examples/triax-tutorial/script-session1.py) run as a batch script with the tutorial's
# parameters, timed per phase and written to JSON.
#
# Usage (yade 2023.02a passes the words after the script name in sys.argv[1:]):
#   yade -n -j1 -x yade_triax.py N SEED OUT.json [key=value ...]
# keys: max_strain (0.15), stress_tol (0.001), unbalanced_tol (0.001),
#       record_every (0.0005, axial strain between curve points), check_every (200 steps),
#       max_steps (3000000, per preparation phase)
#
# Conventions of TriaxialStressController (yade 2023.02a): stresses positive in tension
# (a compressed sample has negative wall stresses and meanStress), strains are logarithmic
# and positive in extension, goal2 < 0 is an axial compression rate. The vertical axis is y.
# Everything written to the JSON file is compression-positive.

import json
import math
import sys
import time

import yade.config
from yade import pack

T_START = time.perf_counter()

# ---------------------------------------------------------------- arguments
argv = sys.argv[1:]
N_SPHERES = int(argv[0]) if len(argv) > 0 else 1000
SEED = int(argv[1]) if len(argv) > 1 else 1
OUT = argv[2] if len(argv) > 2 else 'yade_b1_%d_%d.json' % (N_SPHERES, SEED)
OPTS = {'max_strain': 0.15, 'stress_tol': 0.001, 'unbalanced_tol': 0.001,
        'record_every': 0.0005, 'check_every': 200, 'max_steps': 3000000}
for word in argv[3:]:
    key, _, value = word.partition('=')
    if key not in OPTS:
        raise SystemExit('unknown option %r (known: %s)' % (key, ', '.join(OPTS)))
    OPTS[key] = type(OPTS[key])(float(value))

# ---------------------------------------------------------------- tutorial parameters
YOUNG = 5e6
CONFINING = 1e4                 # Pa, compression
TARGET_POROSITY = 0.43
COMPACTION_FRICTION_DEG = 30.0  # start of the friction reduction
FINAL_FRICTION_DEG = 30.0       # during the deviatoric loading
STRAIN_RATE = 0.02              # 1/s, compression; yade's goal2 = -STRAIN_RATE
DAMPING_PREP = 0.2
DAMPING_SHEAR = 0.1
FRICTION_FACTOR = 0.95
FRICTION_INTERVAL = 500         # steps between two friction reductions
POROSITY_CHECK = 50             # steps between two porosity checks in that phase

lo, hi = Vector3(0, 0, 0), Vector3(1, 1, 1)

O.materials.append(FrictMat(young=YOUNG, poisson=0.5, frictionAngle=radians(COMPACTION_FRICTION_DEG),
                            density=2600, label='spheres'))
O.materials.append(FrictMat(young=YOUNG, poisson=0.5, frictionAngle=0, density=0, label='walls'))

# Six walls first, so that their ids 0..5 are the controller's defaults
# (left 0, right 1, bottom 2, top 3, back 4, front 5).
O.bodies.append(aabbWalls([lo, hi], thickness=0, material='walls'))
LEFT, RIGHT, BOTTOM, TOP, BACK, FRONT = range(6)

cloud = pack.SpherePack()
cloud.makeCloud(lo, hi, -1, 0.3333, N_SPHERES, False, 0.95, seed=SEED)
O.bodies.append([sphere(c, r, material='spheres') for c, r in cloud])
n_placed = len(cloud)

triax = TriaxialStressController(
    maxMultiplier=1. + 2e4 / YOUNG,
    finalMaxMultiplier=1. + 2e3 / YOUNG,
    thickness=0,
    stressMask=7,
    internalCompaction=True,
)
newton = NewtonIntegrator(damping=DAMPING_PREP)


def wall_state():
    """Box sizes (x, y, z) and compression-positive wall stresses (x, y, z), from the wall
    positions and the forces of the current step (mean of the two opposite walls)."""
    pos = [O.bodies[i].state.pos for i in range(6)]
    w = pos[RIGHT][0] - pos[LEFT][0]
    h = pos[TOP][1] - pos[BOTTOM][1]
    d = pos[FRONT][2] - pos[BACK][2]
    f = [O.forces.f(i) for i in range(6)]
    sx = 0.5 * (f[RIGHT][0] - f[LEFT][0]) / (h * d)
    sy = 0.5 * (f[TOP][1] - f[BOTTOM][1]) / (w * d)
    sz = 0.5 * (f[FRONT][2] - f[BACK][2]) / (w * h)
    return (w, h, d), (sx, sy, sz)


curve = {'axial_strain': [], 'axial_strain_log': [], 'volumetric_strain': [], 'sigma1': [],
         'sigma3': [], 'sigma_x': [], 'sigma_z': [], 'q': [], 'porosity': [], 'step': []}
REF = {}          # box sizes at the start of compression
NEXT = [0.0]      # next axial strain to record


def record():
    """Called every step during compression (before NewtonIntegrator)."""
    (w, h, d), (sx, sy, sz) = wall_state()
    eps = (REF['h'] - h) / REF['h']
    if eps < NEXT[0] and eps < OPTS['max_strain']:
        return
    NEXT[0] += OPTS['record_every']
    s3 = min(sx, sz)
    curve['axial_strain'].append(eps)
    curve['axial_strain_log'].append(-math.log(h / REF['h']))
    curve['volumetric_strain'].append(1.0 - w * h * d / REF['v'])
    curve['sigma1'].append(sy)
    curve['sigma3'].append(s3)
    curve['sigma_x'].append(sx)
    curve['sigma_z'].append(sz)
    curve['q'].append(sy - s3)
    curve['porosity'].append(triax.porosity)
    curve['step'].append(O.iter)
    if eps >= OPTS['max_strain']:
        O.pause()


O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
                    [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    GlobalStiffnessTimeStepper(active=1, timeStepUpdateInterval=100, timestepSafetyCoefficient=0.8),
    triax,
    PyRunner(iterPeriod=1, command='record()', dead=True, label='recorder'),
    newton,
]

# ---------------------------------------------------------------- phase 1: compaction
# Radius growth (walls fixed) to an isotropic 10 kPa; maxMultiplier until the mean stress
# first reaches the goal, then finalMaxMultiplier (the controller switches by itself).
t0 = time.perf_counter()
triax.goal1 = triax.goal2 = triax.goal3 = -CONFINING
while True:
    O.run(OPTS['check_every'], True)
    unb = unbalancedForce()
    if unb < OPTS['unbalanced_tol'] and abs(-CONFINING - triax.meanStress) / CONFINING < OPTS['stress_tol']:
        break
    if O.iter > OPTS['max_steps']:
        raise SystemExit('compaction did not converge in %d steps' % O.iter)
t1 = time.perf_counter()
steps_compaction = O.iter
porosity_after_compaction = triax.porosity
unbalanced_after_compaction = unb
mean_stress_after_compaction = -triax.meanStress

# ---------------------------------------------------------------- phase 2: friction reduction
# The tutorial's loop: friction angle x 0.95, 500 steps, while porosity > 0.43; here the
# porosity is also checked every 50 steps inside each 500-step block so that the phase stops
# as soon as the target is reached (as geodem does).
friction = COMPACTION_FRICTION_DEG
reductions = 0
while triax.porosity > TARGET_POROSITY:
    if friction < 1e-3:
        break
    friction *= FRICTION_FACTOR
    reductions += 1
    setContactFriction(radians(friction))
    for _ in range(FRICTION_INTERVAL // POROSITY_CHECK):
        O.run(POROSITY_CHECK, True)
        if triax.porosity <= TARGET_POROSITY:
            break
    if O.iter > steps_compaction + OPTS['max_steps']:
        raise SystemExit('friction reduction did not reach the porosity')
t2 = time.perf_counter()
steps_friction = O.iter - steps_compaction
porosity_after_preparation = triax.porosity
mean_stress_after_preparation = -triax.meanStress

# ---------------------------------------------------------------- phase 3: compression
triax.internalCompaction = False
setContactFriction(radians(FINAL_FRICTION_DEG))
triax.stressMask = 5              # x and z stress-controlled, y strain-rate-controlled
triax.goal2 = -STRAIN_RATE        # negative: compression (strains positive in extension)
triax.goal1 = -CONFINING
triax.goal3 = -CONFINING
newton.damping = DAMPING_SHEAR
(w0, h0, d0), _ = wall_state()
REF.update(w=w0, h=h0, d=d0, v=w0 * h0 * d0)
recorder.dead = False
O.run()
O.wait()
t3 = time.perf_counter()
steps_compression = O.iter - steps_compaction - steps_friction

# ---------------------------------------------------------------- results
q = curve['q']
ip = max(range(len(q)), key=lambda i: q[i])
s1p, s3p = curve['sigma1'][ip], curve['sigma3'][ip]
result = {
    'code': 'yade',
    'yade_version': yade.config.version,
    'n_spheres': n_placed,
    'n_requested': N_SPHERES,
    'seed': SEED,
    'options': OPTS,
    'porosity_after_compaction': porosity_after_compaction,
    'mean_stress_after_compaction': mean_stress_after_compaction,
    'unbalanced_after_compaction': unbalanced_after_compaction,
    'porosity_after_preparation': porosity_after_preparation,
    'mean_stress_after_preparation': mean_stress_after_preparation,
    'friction_deg_reached': friction,
    'friction_reductions': reductions,
    'porosity_initial': curve['porosity'][0],
    'peak_q': q[ip],
    'axial_strain_at_peak': curve['axial_strain'][ip],
    'phi_peak_deg': math.degrees(math.asin(q[ip] / (s1p + s3p))),
    'sigma1_at_peak': s1p,
    'sigma3_at_peak': s3p,
    'final_axial_strain': curve['axial_strain'][-1],
    'final_dt': O.dt,
    # cross-check of the sign convention: the controller's own wall stresses (tension
    # positive, refreshed every 10 steps) negated, against the compression-positive ones above
    'controller_stress_end': {'x': -triax.stress(LEFT)[0], 'y': -triax.stress(BOTTOM)[1],
                              'z': -triax.stress(BACK)[2]},
    'wall_stress_end': {'x': curve['sigma_x'][-1], 'y': curve['sigma1'][-1], 'z': curve['sigma_z'][-1]},
    'steps': {'compaction': steps_compaction, 'friction_reduction': steps_friction,
              'compression': steps_compression, 'total': O.iter},
    'wall_s': {'setup': t0 - T_START, 'compaction': t1 - t0, 'friction_reduction': t2 - t1,
               'compression': t3 - t2, 'total': time.perf_counter() - T_START},
    'curve': curve,
}
with open(OUT, 'w') as fh:
    json.dump(result, fh, indent=1)
print('B1 yade N=%d seed=%d: porosity %.4f, peak q %.1f Pa at %.4f, phi %.2f deg, %d steps, %.1f s'
      % (n_placed, SEED, porosity_after_preparation, q[ip], curve['axial_strain'][ip],
         result['phi_peak_deg'], O.iter, result['wall_s']['total']))
sys.stdout.flush()
# -x would otherwise leave yade to exit on its own; make the exit explicit.
import os
os._exit(0)
