#!/usr/bin/env bash
# Grain refinement of the L-shaped anchors: each example's 3 seeds at grain sizes 1,
# 1/sqrt(2) and 1/2 times its own (same micro parameters, geometry and sheet; up to about
# 15,000 grains a run), pulled to 200 mm (the peaks lie at 26-164 mm). Prints each
# summary's refinement block; the figures go to expected/. About 50-65 minutes on 2 cores.
#
# More seeds: FIRST_SEED=4 FACTORS='[1.0, 0.5]' refine_L.sh runs/refine46 runs seeds 4-6 at
# the full and the half grain size (about 33 minutes) and prints the same lines; its figures
# stay in the output folder (expected/ keeps those of seeds 1-3). Arguments after OUT go to
# every run (e.g. --set sheet.bending_stiffness=50); expected/ is then left as it is.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-runs/refine}
shift || true
FIRST_SEED=${FIRST_SEED:-1}
FACTORS=${FACTORS:-[1.0, 0.7071, 0.5]}
for name in L_silt L_sand; do
  ./build/geodem run "examples/pullout2d/$name.toml" --out "$OUT/$name" --overwrite --threads 2 --quiet \
    --set "seed=$FIRST_SEED" --set "refinement.radius_factors=$FACTORS" \
    --set pull.max_displacement=0.2 --set 'pull.profiles_at=[0.02, 0.1, 0.2]' "$@"
  if [ "$FIRST_SEED" = 1 ] && [ $# = 0 ]; then
    cp "$OUT/$name/pullout_refinement.png" "examples/pullout2d/expected/${name}_refinement.png"
    cp "$OUT/$name/pullout_seeds.png" "examples/pullout2d/expected/${name}_refinement_seeds.png"
  fi
  python3 - "$OUT/$name/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
r = s["results"]
print(sys.argv[1], "refinement:", json.dumps(r.get("refinement")))
for g in r["groups"]:
    t = g["T_max"]
    print(f"  radius {g['radius'] * 1e3:.2f} mm, d50/cover {g['d50_over_cover']:.3f}:"
          f" T_max {t['mean'] / 1e3:.2f} +- {t['std'] / 1e3:.2f} kN/m (cv {100 * t['cv']:.0f} %),"
          f" grains {g['grains']['mean']:.0f}, wall {g['wall_s']['mean']:.0f} s/run,"
          f" mechanisms {g['mechanisms']}, T_slip {g['T_analytic_slip']['mean'] / 1e3:.2f},"
          f" T_soil {g['T_analytic_soil']['mean'] / 1e3:.2f}")
PY
done
