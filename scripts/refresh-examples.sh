#!/usr/bin/env bash
# Re-measures the examples' expected figures with the code as it is:
#
#   scripts/refresh-examples.sh [--all] [OUT]
#
# Runs the single-run examples (deposit2d, deposit3d, staged2d, triaxial3d, biaxial2d, grain_shape2d;
# about 3 minutes on 2 cores) into OUT (default runs/examples), compares the figures their
# READMEs quote with the committed ones (examples/NAME/expected/numbers.json: a difference is
# printed, and means the README's table must be updated too), then writes the new figures
# and plots into expected/. With --all, also the pull-out, interface shear and study
# examples' own refresh scripts, the Python examples and the staged scene's seeds (about an
# hour); their READMEs' tables are then updated by hand from what they print. Exit 1 when a figure changed.
# CTest's examples.quick runs deposit2d and deposit3d and compares their figures.
set -euo pipefail
cd "$(dirname "$0")/.."
all=0
if [[ "${1:-}" == "--all" ]]; then all=1; shift; fi
OUT=${1:-runs/examples}
changed=0
for ex in deposit2d deposit3d staged2d triaxial3d biaxial2d grain_shape2d; do
  dir="examples/$ex"
  ./build/geodem run "$dir/scenario.toml" --out "$OUT/$ex" --overwrite --quiet --threads 1
  if [[ -f "$dir/expected/numbers.json" ]] &&
    ! python3 scripts/example_numbers.py "$OUT/$ex" --compare "$dir/expected/numbers.json"; then
    changed=1
  fi
  python3 scripts/example_numbers.py "$OUT/$ex" > "$dir/expected/numbers.json"
  for png in "$OUT/$ex"/*.png; do
    [[ -f "$dir/expected/$(basename "$png")" ]] && cp "$png" "$dir/expected/"
  done
  echo "$ex: $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['timing']['wall_s'])" \
    "$OUT/$ex/summary.json") s"
done
if ((all)); then
  examples/pullout2d/refresh_expected.sh "$OUT/pullout2d"
  examples/interface_shear2d/refresh_expected.sh "$OUT/interface_shear2d"
  # The Python example (seeds 1-3 in its README; seed 1's figures in expected/).
  for seed in 1 2 3; do
    PYTHONPATH=build/python python3 examples/python/oedometer_servo.py "$OUT/python/seed$seed" "$seed"
  done
  cp "$OUT/python/seed1/oedometer.png" examples/python/expected/
  cp "$OUT/python/seed1/oedometer.json" examples/python/expected/oedometer_seed1.json
  # The triaxial tutorial (seeds 1-3 in the README; seed 1's in expected/) and the sweep.
  for seed in 1 2 3; do
    PYTHONPATH=build/python python3 examples/python/triaxial_tutorial.py "$OUT/python/triax$seed" "$seed"
  done
  cp "$OUT/python/triax1/triaxial.png" examples/python/expected/triaxial_tutorial.png
  python3 -c "import json,sys; json.dump(json.load(open(sys.argv[1]))['results'], open(sys.argv[2], 'w'), indent=1)" \
    "$OUT/python/triax1/triaxial.json" examples/python/expected/triaxial_tutorial_seed1.json
  PYTHONPATH=build/python python3 examples/python/friction_sweep.py "$OUT/python/sweep"
  cp "$OUT/python/sweep/friction_sweep.png" "$OUT/python/sweep/sweep.json" examples/python/expected/
  # The triaxial test between walls and in a periodic cell (seeds 1-3), and the
  # critical-state comparison of drained and undrained biaxial tests in a periodic cell.
  /usr/bin/python3 examples/triaxial3d/compare_boundaries.py "$OUT/triaxial3d_boundaries"
  cp "$OUT/triaxial3d_boundaries/boundaries.png" "$OUT/triaxial3d_boundaries/boundaries.md" \
    examples/triaxial3d/expected/
  # The element tests of one soil over 5 seeds (about 4 minutes), seed 1's plots.
  /usr/bin/python3 examples/triaxial3d/direct_shear_seeds.py "$OUT/triaxial3d_direct_shear"
  cp "$OUT/triaxial3d_direct_shear"/direct_shear{.md,_seeds.png} examples/triaxial3d/expected/
  /usr/bin/python3 examples/lab2d/consistency.py "$OUT/lab2d" --seeds 5
  cp "$OUT/lab2d"/consistency.{md,json} "$OUT/lab2d"/{modulus_damping,compression}.png \
    examples/lab2d/expected/
  /usr/bin/python3 examples/lab2d/consistency.py "$OUT/lab2d_sand" --seeds 5 --soil sand_2d
  cp "$OUT/lab2d_sand"/consistency.{md,json} "$OUT/lab2d_sand"/{modulus_damping,compression}.png \
    examples/lab2d/expected/sand_2d/
  for k in oedometer direct_shear simple_shear cyclic; do
    /usr/bin/python3 python/geodem_plot.py "$OUT/lab2d/${k}_seed1" > /dev/null
  done
  cp "$OUT/lab2d/oedometer_seed1/k0.png" "$OUT/lab2d/direct_shear_seed1/direct_shear.png" \
    "$OUT/lab2d/simple_shear_seed1/simple_shear.png" "$OUT/lab2d/cyclic_seed1/loops.png" \
    examples/lab2d/expected/
  /usr/bin/python3 examples/biaxial2d/critical_state.py "$OUT/biaxial2d_critical_state" --strain 0.2 \
    --count 1000
  cp "$OUT/biaxial2d_critical_state/critical_state.png" \
    "$OUT/biaxial2d_critical_state/critical_state.md" examples/biaxial2d/expected/
  # The staged scene's seed table.
  python3 examples/staged2d/seeds.py build/geodem "$OUT/staged2d_seeds"
fi
if ((changed)); then
  echo "figures changed: update the examples' READMEs (and docs quoting them) from expected/numbers.json"
fi
exit "$changed"
