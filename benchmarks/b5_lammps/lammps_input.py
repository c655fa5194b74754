#!/usr/bin/env python3
"""Write the LAMMPS input of benchmark B5: B2's settle and dense bed in LAMMPS (GRANULAR).

usage: lammps_input.py OUTDIR --law hooke|hertz [--settle 50000] [--dense 10000] [--lx L]

Reads nothing and writes OUTDIR/in.<law>; the data file OUTDIR/data.settle3d comes from
../b2_settle3d/liggghts_input.py (atom_style sphere reads its "id type diameter density x y
z" lines as they are), so LAMMPS, LIGGGHTS and geodem start from the same lattice.

hooke: `pair_style gran/hooke/history` and `fix wall/gran hooke/history` with the constants
LIGGGHTS' Hooke model derives for B2 (../b2_settle3d/LIGGGHTS_NOTES.md), which geodem's B2
scenario uses too: kn = kt = 8072.3074 N/m between grains, 12235.330 N/m against walls,
restitution 0.5 through the same viscous coefficients (LAMMPS takes them per unit of
effective mass: gamma_n/m* = 535.04 /s between grains, 465.78 /s against walls), the same
coefficient on the tangential dashpot (dampflag 1), friction 0.5.

hertz: `pair_style gran/hertz/history` with Kn = 4/3 E* and Kt = 8 G* (Y = 5 MPa, nu =
0.25), against geodem's Hertz-Mindlin law with the same moduli. LAMMPS' Hertz dashpot is
m* gamma_n sqrt(R* delta) and geodem's Tsuji form 2 sqrt(5/6) beta sqrt(2 E* a m*): they
differ, so the damping is matched at the mean overlap of the settled bed only and the two
beds are compared by height, not bit for bit; the case times the Hertz force loop.
"""
import argparse
import math
import os

R, RHO, G = 0.01, 2500.0, 9.81
DT, SKIN, FRICTION = 2.0e-5, 0.002, 0.5
YOUNG, POISSON = 5.0e6, 0.25
KN_PP, KN_PW = 8072.3074, 12235.330          # N/m (LIGGGHTS_NOTES.md)
GAMMA_PP, GAMMA_PW = 2.8014459, 4.8776005     # N s/m
MASS = 4.0 / 3.0 * math.pi * R ** 3 * RHO
ESTAR = 1.0 / (2.0 * (1.0 - POISSON ** 2) / YOUNG)
GSTAR = 1.0 / (2.0 * 2.0 * (2.0 - POISSON) * (1.0 + POISSON) / YOUNG)


def hertz_gamma(mstar, rstar, delta=1e-4):
    """LAMMPS' gamma_n (1/(s m)) that gives geodem's Tsuji dashpot at overlap `delta`:
    m* gamma sqrt(R* delta) = 2 sqrt(5/6) beta sqrt(2 E* sqrt(R* delta) m*), beta of e = 0.5."""
    beta = -math.log(0.5) / math.sqrt(math.log(0.5) ** 2 + math.pi ** 2)
    a = math.sqrt(rstar * delta)
    return 2.0 * math.sqrt(5.0 / 6.0) * beta * math.sqrt(2.0 * ESTAR * a * mstar) / (mstar * a)


def input_text(law, lx, ly, lz, settle, dense):
    if law == "hooke":
        pair = f"gran/hooke/history {KN_PP} {KN_PP} {GAMMA_PP / (MASS / 2):.6f} " \
               f"{GAMMA_PP / (MASS / 2):.6f} {FRICTION} 1"
        wall = f"hooke/history {KN_PW} {KN_PW} {GAMMA_PW / MASS:.6f} {GAMMA_PW / MASS:.6f} {FRICTION} 1"
    else:
        kn, kt = 4.0 / 3.0 * ESTAR, 8.0 * GSTAR
        gpp, gpw = hertz_gamma(MASS / 2, R / 2), hertz_gamma(MASS, R)
        pair = f"gran/hertz/history {kn:.6f} {kt:.6f} {gpp:.6f} {gpp:.6f} {FRICTION} 1"
        wall = f"hertz/history {kn:.6f} {kt:.6f} {gpw:.6f} {gpw:.6f} {FRICTION} 1"
    planes = [("xplane", 0.0, lx), ("yplane", 0.0, ly), ("zplane", 0.0, lz)]
    walls = "\n".join(f"fix             w{k} all wall/gran {wall} {p} {lo} {hi}"
                      for k, (p, lo, hi) in enumerate(planes))
    return f"""# B5: B2 settle3d in LAMMPS, {law} law (written by lammps_input.py)
units           si
atom_style      sphere
atom_modify     map array
boundary        f f f
newton          off
comm_modify     vel yes
read_data       data.settle3d
neighbor        {SKIN} bin
neigh_modify    delay 0
pair_style      {pair}
pair_coeff      * *
timestep        {DT}
fix             gravi all gravity {G} vector 0.0 0.0 -1.0
{walls}
fix             integr all nve/sphere
compute         rke all erotate/sphere
compute         zmax all reduce max z
thermo_style    custom step atoms ke c_rke c_zmax cpu
thermo          5000
thermo_modify   norm no flush yes
# phase 1: settle
run             {settle}
# phase 2: timed steps on the settled bed
run             {dense}
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--law", choices=("hooke", "hertz"), default="hooke")
    ap.add_argument("--settle", type=int, default=50000)
    ap.add_argument("--dense", type=int, default=10000)
    ap.add_argument("--lx", type=float, required=True, help="box side in x and y (m)")
    ap.add_argument("--lz", type=float, default=1.2)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, f"in.{a.law}"), "w") as f:
        f.write(input_text(a.law, a.lx, a.lx, a.lz, a.settle, a.dense))


if __name__ == "__main__":
    main()
