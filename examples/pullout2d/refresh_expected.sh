#!/usr/bin/env bash
# Re-measures the pull-out examples (each over its seeds) and refreshes expected/: the
# plots of every example (all seeds' curves and their mean; the tension each part of the
# sheet takes off, averaged over the seeds; seed 1's soil bands before and after the pull) and expected/table.md, the table of README.md. Run from the repository
# root after scripts/build.sh; OUT (default runs/pullout2d) keeps the runs, and a rerun
# reuses the finished ones. About 20 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-runs/pullout2d}
EXPECTED=examples/pullout2d/expected
mkdir -p "$OUT" "$EXPECTED"
for name in L_sand L_silt V_sand runout_sand runout_silt; do
  ./build/geodem run "examples/pullout2d/$name.toml" --out "$OUT/$name" --overwrite --threads 2 --quiet
  cp "$OUT/$name/pullout_seeds.png" "$EXPECTED/${name}_seeds.png"
  cp "$OUT/$name/pullout_sheet_parts.png" "$EXPECTED/${name}_sheet_parts.png"
  ./build/geodem plot "$OUT/$name/runs/seed1" > /dev/null
  for fig in pullout pullout_initial pullout_final tension_profiles; do
    cp "$OUT/$name/runs/seed1/$fig.png" "$EXPECTED/${name}_$fig.png"
  done
done
python3 examples/pullout2d/pullout_table.py "$OUT" > "$EXPECTED/table.md"
cat "$EXPECTED/table.md"
# The run-out series against the estimate, and the biaxial tests of both soils.
python3 examples/pullout2d/runout_study.py "$OUT/runout_study" | tee "$EXPECTED/runout_study.md"
for soil in sand silt; do
  ./build/geodem run "examples/pullout2d/soil_${soil}_biaxial.toml" --out "$OUT/soil_$soil" --overwrite --quiet \
    --threads 2
  cp "$OUT/soil_$soil/mohr_coulomb.png" "$EXPECTED/soil_${soil}_mohr_coulomb.png"
done
