#!/usr/bin/env bash
# The main job: install what is missing, build, run the flagship example.
# Outputs (CSV, JSON, VTK, PNG) land in out/deposit3d.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
./build/geodem run examples/deposit3d/scenario.toml --out out/deposit3d
echo "outputs: $(pwd)/out/deposit3d (summary.json, history.csv, vtk/particles.pvd, *.png)"
