#!/usr/bin/env python3
"""Write the LIGGGHTS input (and initial particle data) for benchmark B2 "settle3d".

Case: N monodisperse spheres (r = 0.01 m, rho = 2500 kg/m3) in a closed box
[0,Lx] x [0,Ly] x [0,Lz] with frictional walls on all six planes, Hooke normal
contact + history tangential contact, mu = 0.5, dt = 2e-5 s, gravity 9.81 in -z.

Phase 1 ("settle"): particles fall and come to rest (SETTLE_STEPS steps).
Phase 2 ("dense"):  DENSE_STEPS (default 10,000) further steps on the settled bed.
Each phase is its own `run`, so LIGGGHTS prints one "Loop time of ..." per phase.

Initial state (default, --insert lattice): all N particles are placed at once,
without overlap, on a simple-cubic lattice of spacing 0.021 m (gap 1 mm) with a
deterministic random jitter of +-0.4 mm per axis (Python random, --seed),
filled bottom-up; they are read with read_data. A plain-text copy of the
positions (id x y z) is written as well so that another engine can start from
the identical state.

Why not fix insert/pack by default: random sequential insertion saturates near
38 % solid fraction; in the 0.4 x 0.4 x 1.2 m box fix insert/pack (overlapcheck
yes, all_in yes, maxattempt 500) places only 15,367 of 20,000 spheres. The
--insert pack mode is kept for smaller N (or a taller box).

Python 3 standard library only.
"""
import argparse
import math
import os
import random
import sys

# ---------------------------------------------------------------- parameters
RADIUS = 0.01            # m
DENSITY = 2500.0         # kg/m3
YOUNG = 5.0e6            # Pa  (LIGGGHTS minimum allowed in SI units)
POISSON = 0.25
RESTITUTION = 0.5
FRICTION = 0.5           # particle-particle and particle-wall
CHAR_VEL = 2.0           # m/s (characteristicVelocity, used by hooke to derive kn)
DT = 2.0e-5              # s
GRAVITY = 9.81           # m/s2, -z
SKIN = 0.002             # m
LATTICE_SPACING = 0.021  # m  (sphere diameter 0.02 + 1 mm gap)
JITTER = 0.0004          # m  (max displacement per axis, keeps >= 0.2 mm gap)

# distinct primes for LIGGGHTS random seeds
SEED_TEMPLATE = 15485863
SEED_DISTRIB = 32452843
SEED_INSERT = 49979687


def default_footprint(n):
    """0.4 m for N <= 20,000, footprint scaled with sqrt(N/20000) above."""
    return 0.4 * math.sqrt(max(1.0, n / 20000.0))


def lattice_positions(n, lx, ly, lz, seed):
    """Return n non-overlapping jittered simple-cubic positions, bottom-up."""
    s = LATTICE_SPACING
    off = RADIUS + (s - 2.0 * RADIUS) / 2.0  # first centre: r + half gap
    nx = int(math.floor((lx - 2.0 * off) / s + 1e-9)) + 1
    ny = int(math.floor((ly - 2.0 * off) / s + 1e-9)) + 1
    nz = int(math.floor((lz - 2.0 * off) / s + 1e-9)) + 1
    cap = nx * ny * nz
    if n > cap:
        sys.exit("error: lattice holds only %d particles (%d x %d x %d) in "
                 "%g x %g x %g m, N = %d requested" % (cap, nx, ny, nz, lx, ly, lz, n))
    # centre the lattice horizontally in the box
    x0 = (lx - (nx - 1) * s) / 2.0
    y0 = (ly - (ny - 1) * s) / 2.0
    z0 = off
    rng = random.Random(seed)
    pos = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                if len(pos) == n:
                    return pos, (nx, ny, nz)
                pos.append((x0 + i * s + rng.uniform(-JITTER, JITTER),
                            y0 + j * s + rng.uniform(-JITTER, JITTER),
                            z0 + k * s + rng.uniform(-JITTER, JITTER)))
    return pos, (nx, ny, nz)


def write_data(path, pos, lx, ly, lz):
    """LAMMPS/LIGGGHTS data file, atom_style granular: id type diameter density x y z."""
    with open(path, "w") as f:
        f.write("B2 settle3d initial state: %d spheres r=%g rho=%g\n\n" % (len(pos), RADIUS, DENSITY))
        f.write("%d atoms\n1 atom types\n\n" % len(pos))
        f.write("0.0 %.10g xlo xhi\n0.0 %.10g ylo yhi\n0.0 %.10g zlo zhi\n\n" % (lx, ly, lz))
        f.write("Atoms\n\n")
        d = 2.0 * RADIUS
        for i, (x, y, z) in enumerate(pos, 1):
            f.write("%d 1 %.10g %.10g %.10g %.10g %.10g\n" % (i, d, DENSITY, x, y, z))


def write_xyz(path, pos):
    with open(path, "w") as f:
        f.write("# id x y z  (m); radius %g m, density %g kg/m3, v = 0\n" % (RADIUS, DENSITY))
        for i, (x, y, z) in enumerate(pos, 1):
            f.write("%d %.10g %.10g %.10g\n" % (i, x, y, z))


def input_text(n, lx, ly, lz, settle_steps, dense_steps, insert, data_name, thermo_every):
    L = []
    a = L.append
    a("# B2 settle3d: %d spheres, box %.6g x %.6g x %.6g m" % (n, lx, ly, lz))
    a("# phase 1: settle %d steps; phase 2: %d timed steps on the settled bed" % (settle_steps, dense_steps))
    a("atom_style      granular")
    a("atom_modify     map array")
    a("boundary        f f f")
    a("newton          off")
    a("communicate     single vel yes")
    a("units           si")
    a("")
    if insert == "lattice":
        a("read_data       %s" % data_name)
    else:
        a("region          domain block 0.0 %.10g 0.0 %.10g 0.0 %.10g units box" % (lx, ly, lz))
        a("create_box      1 domain")
    a("")
    a("neighbor        %g bin" % SKIN)
    a("neigh_modify    delay 0")
    a("")
    a("# material (one atom type; the walls use the same type)")
    a("fix m1 all property/global youngsModulus peratomtype %g" % YOUNG)
    a("fix m2 all property/global poissonsRatio peratomtype %g" % POISSON)
    a("fix m3 all property/global coefficientRestitution peratomtypepair 1 %g" % RESTITUTION)
    a("fix m4 all property/global coefficientFriction peratomtypepair 1 %g" % FRICTION)
    a("fix m5 all property/global characteristicVelocity scalar %g" % CHAR_VEL)
    a("")
    a("pair_style      gran model hooke tangential history")
    a("pair_coeff      * *")
    a("timestep        %g" % DT)
    a("fix gravi all gravity %g vector 0.0 0.0 -1.0" % GRAVITY)
    a("")
    a("# frictional walls on all six planes")
    wg = "wall/gran model hooke tangential history primitive type 1"
    a("fix wx0 all %s xplane 0.0" % wg)
    a("fix wx1 all %s xplane %.10g" % (wg, lx))
    a("fix wy0 all %s yplane 0.0" % wg)
    a("fix wy1 all %s yplane %.10g" % (wg, ly))
    a("fix wz0 all %s zplane 0.0" % wg)
    a("fix wz1 all %s zplane %.10g" % (wg, lz))
    a("")
    if insert == "pack":
        a("# insert all particles at once (works only below ~38 % solid fraction)")
        a("fix pts1 all particletemplate/sphere %d atom_type 1 density constant %g radius constant %g"
          % (SEED_TEMPLATE, DENSITY, RADIUS))
        a("fix pdd1 all particledistribution/discrete %d 1 pts1 1.0" % SEED_DISTRIB)
        a("fix ins all insert/pack seed %d distributiontemplate pdd1 maxattempt 500 "
          "insert_every once overlapcheck yes all_in yes vel constant 0.0 0.0 0.0 "
          "region domain particles_in_region %d" % (SEED_INSERT, n))
        a("")
    a("fix integr all nve/sphere")
    a("")
    a("# monitoring: translational ke, rotational ke, max speed, max z (total, not normalised)")
    a("compute rke all erotate/sphere")
    a("variable vmag atom sqrt(vx*vx+vy*vy+vz*vz)")
    a("compute vmax all reduce max v_vmag")
    a("compute zmax all reduce max z")
    a("thermo_style    custom step atoms ke c_rke c_vmax c_zmax cpu")
    a("thermo          %d" % thermo_every)
    a("thermo_modify   norm no flush yes")
    a("")
    a("# phase 1: settle")
    a("run             %d" % settle_steps)
    a("")
    a("# phase 2: timed steps on the settled bed")
    a("run             %d" % dense_steps)
    a("")
    return "\n".join(L)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("-n", "--n", type=int, required=True, help="number of particles")
    p.add_argument("--lx", type=float, default=None, help="box x (default 0.4*sqrt(max(1,N/20000)))")
    p.add_argument("--ly", type=float, default=None, help="box y (default = lx)")
    p.add_argument("--lz", type=float, default=1.2, help="box z (default 1.2)")
    p.add_argument("--settle-steps", type=int, default=50000)
    p.add_argument("--dense-steps", type=int, default=10000)
    p.add_argument("--thermo", type=int, default=1000, help="thermo output interval")
    p.add_argument("--insert", choices=("lattice", "pack"), default="lattice")
    p.add_argument("--seed", type=int, default=12345, help="jitter seed for the lattice")
    p.add_argument("-o", "--outdir", default=".")
    p.add_argument("--input-name", default="in.settle")
    a = p.parse_args()

    lx = a.lx if a.lx is not None else default_footprint(a.n)
    ly = a.ly if a.ly is not None else lx
    lz = a.lz
    os.makedirs(a.outdir, exist_ok=True)
    data_name = "data.settle3d"
    if a.insert == "lattice":
        pos, dims = lattice_positions(a.n, lx, ly, lz, a.seed)
        write_data(os.path.join(a.outdir, data_name), pos, lx, ly, lz)
        write_xyz(os.path.join(a.outdir, "initial_positions.txt"), pos)
        top = max(z for _, _, z in pos) + RADIUS
        print("lattice %d x %d x %d, %d particles, initial top %.4f m" % (dims + (a.n, top)), file=sys.stderr)
    with open(os.path.join(a.outdir, a.input_name), "w") as f:
        f.write(input_text(a.n, lx, ly, lz, a.settle_steps, a.dense_steps, a.insert, data_name, a.thermo))
    print("box %.6g %.6g %.6g" % (lx, ly, lz))


if __name__ == "__main__":
    main()
