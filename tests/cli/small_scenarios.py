"""Small scenarios shared by the command-line tests, the crash harness
(tests/crash/crash_harness.py) and the robustness sweep (tests/robustness/seed_sweep.py):
each a quick case of its kind (seconds), as text to write into a scenario file."""

SMALL_SCENE = """
kind = "scene"
dimension = {dim}
[time]
step = "auto"
duration = 0.05
[physics]
gravity = {gravity}
local_damping = 0.2
[[materials]]
name = "sand"
young = 1e6
friction = 0.5
[[walls]]
name = "floor"
normal = {normal}
area = 0.01
[[clouds]]
min = {lo}
max = {hi}
count = 50
radius = 0.004
[output]
history_every = 50
"""

# A run-out anchor in a small frictional soil box (about 600 discs): the quick version of
# the run-out comparison of docs/lab_tests.md. Interface friction (20 deg) well below the
# soil's, and a front wall that keeps the cover in the box: the sheet slips out of the soil.
SMALL_PULLOUT = """
kind = "pullout"
seed = 1
[box]
length = 0.8
foundation = 0.12
[soil]
density = 2600.0
young = 2e7
friction_deg = 30.0
radius = 0.008
radius_fuzz = 0.25
[anchor]
shape = "{shape}"
runout_length = 0.5
cover = 0.1
front = "wall"
{trench}
[sheet]
stiffness_J = 1e5
interface_friction_deg = 20.0
[pull]
rate = 0.02
max_displacement = 0.03
[analytic]
soil_friction_deg = 30.0
"""

# A bed of 3,000 spheres with rolling resistance (contact state beyond the spring), VTK
# frames, and a checkpoint every 300 steps: about 3,300 steps, 2 s on one core.
CHECKPOINT_SCENE = """
kind = "scene"
dimension = 3
[time]
step = "auto"
duration = 0.3
[physics]
gravity = [0, 0, -9.81]
local_damping = 0.2
[[materials]]
name = "sand"
young = 1e6
friction = 0.5
rolling_friction = 0.1
[[walls]]
name = "floor"
normal = [0, 0, 1]
area = 0.01
[[clouds]]
min = [0, 0, 0]
max = [0.1, 0.1, 0.1]
count = 3000
radius = 0.002
[output]
history_every = 20
vtk_every = 500
plots = false
[checkpoint]
every_steps = 300
"""

# A small biaxial test that passes through every stage of the triaxial kind: clumps, rolling
# resistance, cohesive bonds made after compaction, friction reduction to a target
# porosity, two confining stresses (each from the prepared sample), VTK frames.
LAB_CHECKPOINT_TRIAXIAL = """
kind = "triaxial"
dimension = 2
seed = 3
[sample]
box = [0.4, 0.8]
count = 150
initial_porosity = 0.9
grain = "pair_0.9"
[material]
density = 2650.0
young = 1e8
kt_over_kn = 0.5
friction = 0.5
rolling_friction = 0.1
normal_cohesion = 5e4
shear_cohesion = 5e4
[compaction]
confining_stress = 1e5
target_porosity = 0.235  # below what compaction at full friction reaches: friction reduction runs
[shear]
strain_rate = 0.05
max_axial_strain = 0.01
confining_stress = [5e4, 1e5]
vtk_at_strains = [0.005]
[output]
plots = false
"""


# A small shear box of two-disc clumps (about 100) on the sheet.
SMALL_SHEAR = """
kind = "interface_shear"
seed = {seed}
[box]
length = 0.2
height = 0.05
base = "{base}"
{lower}
[soil]
density = 2600.0
young = 2e7
kt_over_kn = 0.5
friction_deg = 30.0
grain = "pair_0.9"
radius = 0.005
deposit_friction_deg = 0.0
[sheet]
interface_friction_deg = {delta}
stiffness_J = 1e6
bending_stiffness = 0.1
[shear]
normal_stress = [10e3, 20e3]
rate = 0.02
max_displacement = {travel}
history_points = 50
[output]
vtk = false
"""


def shear(delta=25.0, base="rigid", seed=1, travel=0.02):
    lower = "lower_height = 0.05" if base == "soil" else ""
    return SMALL_SHEAR.format(delta=delta, base=base, lower=lower, seed=seed, travel=travel)


# A small 2D biaxial base for the studies (add kind and the study table).
BASE = """
dimension = 2
seed = 1
[sample]
box = [0.4, 0.8]
count = 100
radius_fuzz = 0.25
initial_porosity = 0.9
[material]
density = 2650.0
young = 1e8
kt_over_kn = 0.5
friction_deg = 30.0
[compaction]
confining_stress = 1e5
damping = 0.2
[shear]
strain_rate = 0.05
max_axial_strain = 0.04
confining_stress = [1e5]
damping = 0.1
[output]
plots = false
"""

# The staged scene of examples/staged2d at a small size (about 300 discs): settle on a
# trap-door gate, remove it, level the deposit, load it with a servo plate.
SMALL_STAGED = """
kind = "scene"
dimension = 2
seed = 1
[time]
step = "auto"
safety = 0.5
[physics]
local_damping = 0.3
[[materials]]
name = "sand"
density = 2650.0
young = 2e6
friction_deg = 30.0
restitution = 0.5
[[walls]]
name = "floor"
normal = [0.0, 1.0]
[[walls]]
name = "left"
normal = [1.0, 0.0]
[[walls]]
name = "right"
point = [0.1, 0.0]
normal = [-1.0, 0.0]
[[walls]]
name = "gate"
point = [0.0, 0.05]
normal = [0.0, 1.0]
[[clouds]]
min = [0.0, 0.05]
max = [0.1, 0.2]
count = 300
radius = 0.002
radius_fuzz = 0.25
[[stages]]
name = "settle"
gravity = [0.0, -9.81]
duration = 1.0
[stages.stop]
unbalanced_below = 2e-3
min_time = 0.2
[[stages]]
name = "drop"
remove_walls = ["gate"]
duration = 1.0
[stages.stop]
unbalanced_below = 2e-3
min_time = 0.1
[[stages]]
name = "excavate"
duration = 0.5
[[stages.remove_grains]]
min = [0.0, 0.035]
max = [0.1, 1.0]
[stages.stop]
unbalanced_below = 2e-3
min_time = 0.02
[[stages]]
name = "load"
duration = 1.0
[[stages.add_walls]]
name = "plate"
point = [0.0, 0.045]
normal = [0.0, -1.0]
area = 0.1
[[stages.walls]]
name = "plate"
servo_stress = 10e3
max_speed = 0.05
[stages.stop]
unbalanced_below = 1e-3
min_time = 0.1
[output]
history_every = 100
vtk = false
plots = false
"""
