#!/usr/bin/env bash
# Run LIGGGHTS on benchmark B2 "settle3d" (one process, no MPI) and report timings.
#
# usage: run_liggghts.sh N OUTDIR [SETTLE_STEPS] [DENSE_STEPS] [extra liggghts_input.py args...]
#   N             number of spheres (box footprint 0.4 m for N <= 20000, scaled by sqrt(N/20000) above)
#   OUTDIR        working directory (input, data file, log, time -v output)
#   SETTLE_STEPS  steps of phase 1 (default 50000)
#   DENSE_STEPS   steps of phase 2 on the settled bed (default 10000)
#
# Prints one line of key=value:
#   n settle_steps settle_loop_s settle_pstep_per_s dense_steps dense_loop_s dense_pstep_per_s
#   peak_rss_kb wall_s final_ke final_zmax
set -euo pipefail

if [ $# -lt 2 ]; then
    sed -n '2,13p' "$0" >&2
    exit 2
fi
N=$1; OUT=$2; SETTLE=${3:-50000}; DENSE=${4:-10000}
shift $(( $# < 4 ? $# : 4 ))
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
LIGGGHTS=${LIGGGHTS:-liggghts}
command -v "$LIGGGHTS" >/dev/null || { echo "liggghts not found (apt-get install -y liggghts)" >&2; exit 1; }

mkdir -p "$OUT"
python3 "$HERE/liggghts_input.py" -n "$N" -o "$OUT" --settle-steps "$SETTLE" --dense-steps "$DENSE" "$@" >/dev/null

cd "$OUT"
export OMP_NUM_THREADS=1
/usr/bin/time -v "$LIGGGHTS" -in in.settle -log log.liggghts > stdout.txt 2> time.txt || {
    echo "liggghts failed, see $OUT/stdout.txt and $OUT/time.txt" >&2; exit 1; }

python3 - "$N" "$SETTLE" "$DENSE" <<'PY'
import re, sys
n, settle, dense = (int(v) for v in sys.argv[1:4])
log = open("log.liggghts").read()
loops = [(float(t), int(s)) for t, s in re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", log)]
if len(loops) < 2:
    sys.exit("expected two 'Loop time' lines, found %d" % len(loops))
(ts, ss), (td, sd) = loops[-2], loops[-1]
tv = open("time.txt").read()
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", tv).group(1))
m = re.search(r"Elapsed \(wall clock\) time.*?: (?:(\d+):)?(\d+):([0-9.]+)", tv)
wall = (int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3))) if m else float("nan")
# last thermo line before the final Loop time: step atoms ke rke vmax zmax cpu
rows = re.findall(r"^\s*(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", log, re.M)
ke = rows[-1][2] if rows else "nan"
zmax = rows[-1][5] if rows else "nan"
print("n=%d settle_steps=%d settle_loop_s=%.3f settle_pstep_per_s=%.4g dense_steps=%d dense_loop_s=%.3f "
      "dense_pstep_per_s=%.4g peak_rss_kb=%d wall_s=%.1f final_ke=%s final_zmax=%s"
      % (n, ss, ts, n * ss / ts, sd, td, n * sd / td, rss, wall, ke, zmax))
PY
