#!/usr/bin/env bash
# The main job: install what is missing, build, run the flagship example (a drained
# triaxial test of 2000 spheres at 100 kPa, examples/triaxial3d).
# Outputs (CSV, JSON, VTK, PNG) land in out/triaxial3d.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
./build/geodem run examples/triaxial3d/scenario.toml --out out/triaxial3d --overwrite
echo "outputs: $(pwd)/out/triaxial3d (summary.json, history.csv, preparation.csv, vtk/particles.pvd, stress_strain.png)"
