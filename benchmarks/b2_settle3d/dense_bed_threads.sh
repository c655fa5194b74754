#!/usr/bin/env bash
# Times 3,000 steps of a settled bed of 200,000 spheres (B2's contacts) on 1 thread, on 2
# threads, and as two 1-thread runs side by side (what the machine allows two cores), all
# resumed from the same checkpoint. Usage: dense_bed_threads.sh [WORKDIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
geodem=${GEODEM:-$here/../../build/geodem}
work=${1:-$here/../results/dense_bed}
mkdir -p "$work" && cd "$work"
cp "$here/dense_bed_200k.toml" bed.toml
[[ -f bed/summary.json ]] || "$geodem" run bed.toml --out bed --threads 2 --quiet
for c in t1 t2 p1 p2; do rm -rf $c; cp -r bed $c; done
run() { "$geodem" run bed.toml --resume "$1" --set time.steps=19000 --threads "$2" --quiet 2>/dev/null; }
run t1 1
run t2 2
run p1 1 & run p2 1 & wait
python3 - <<'PY'
import json
b = json.load(open("bed/summary.json"))["timing"]
for c, what in (("t1", "1 thread"), ("t2", "2 threads"), ("p1", "1 thread beside another"),
                ("p2", "1 thread beside another")):
    t = json.load(open(c + "/summary.json"))["timing"]
    w = t["wall_s"] - b["wall_s"]
    st = {k: round(t["stages_s"][k] - b["stages_s"][k], 2) for k in t["stages_s"] if t["stages_s"][k] > 0}
    print(f"{what}: {w:.1f} s, {200000 * 3000 / w / 1e6:.2f} M particle-steps/s, stages {st}")
PY
