#!/usr/bin/env bash
# Re-measures the interface shear examples and refreshes expected/: both soils with their
# calibrated interface (plots and summary figures), the table of macroscopic against local
# interface friction (delta_table.py, 3 seeds) and, with --calibrate, first the two interface
# calibrations, which set the presets' [interface] tables (set_preset_interface.py). Run
# from the repository root after scripts/build.sh; OUT defaults to runs/interface_shear2d. About 8 minutes on 2 cores
# (4 more with --calibrate).
set -euo pipefail
cd "$(dirname "$0")/../.."
CALIBRATE=0
if [ "${1:-}" = "--calibrate" ]; then CALIBRATE=1; shift; fi
OUT=${1:-runs/interface_shear2d}
EXPECTED=examples/interface_shear2d/expected
mkdir -p "$OUT" "$EXPECTED"
if [ $CALIBRATE = 1 ]; then
  # First the calibrations, whose results the presets (and so the examples below) take.
  for soil in sand silt; do
    ./build/geodem run "examples/interface_shear2d/calibrate_$soil.toml" --out "$OUT/calibrate_$soil" --overwrite \
      --threads 2 --quiet
    cp "$OUT/calibrate_$soil/interface_calibration.png" "$EXPECTED/${soil}_interface_calibration.png"
  done
  python3 examples/interface_shear2d/set_preset_interface.py "$OUT"
fi
for soil in sand silt; do
  ./build/geodem run "examples/interface_shear2d/$soil.toml" --out "$OUT/$soil" --overwrite --threads 2 --quiet
  cp "$OUT/$soil/interface_shear.png" "$EXPECTED/${soil}_interface_shear.png"
  cp "$OUT/$soil/interface_envelope.png" "$EXPECTED/${soil}_interface_envelope.png"
done
python3 - "$OUT" > "$EXPECTED/examples.md" <<'PY'
import json, sys
out = sys.argv[1]
print("| soil | local friction (deg) | macro friction, peak (deg) | adhesion, peak (kPa) |"
      " macro friction, residual (deg) | per test: peak friction (deg) at 5 / 10 / 20 kPa |"
      " grains | wall time (s) |")
print("| --- | ---: | ---: | ---: | ---: | --- | ---: | ---: |")
for soil in ("sand", "silt"):
    s = json.load(open(f"{out}/{soil}/summary.json"))
    r = s["results"]
    tests = " / ".join(f"{t['peak_friction_deg']:.1f}" for t in r["tests"])
    print(f"| {soil} | {r['local_interface_friction_deg']:.2f} |"
          f" {r['interface_friction_peak_deg']:.2f} | {r['interface_adhesion_peak'] / 1e3:.2f} |"
          f" {r['interface_friction_residual_deg']:.2f} | {tests} | {r['deposit_grains']} |"
          f" {s['timing']['wall_s']:.0f} |")
PY
cat "$EXPECTED/examples.md"
python3 examples/interface_shear2d/delta_table.py "$OUT/delta_table" --seeds 3 | tee "$EXPECTED/delta_table.md"
# Confined dilatancy: the silt at constant normal stiffnesses (about 30 s).
python3 examples/interface_shear2d/cns_table.py "$OUT/cns" | tee "$EXPECTED/cns_table.md"
