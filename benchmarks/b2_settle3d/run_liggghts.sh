#!/usr/bin/env bash
# Run LIGGGHTS on benchmark B2 "settle3d" (one process, no MPI) and report timings.
#
# usage: run_liggghts.sh N OUTDIR [SETTLE_STEPS] [DENSE_STEPS] [extra liggghts_input.py args...]
#   N             number of spheres (box footprint 0.4 m for N <= 20000, scaled by sqrt(N/20000) above)
#   OUTDIR        working directory (input, data file, log, `time -v` output)
#   SETTLE_STEPS  steps of phase 1 (default 50000)
#   DENSE_STEPS   steps of phase 2 on the settled bed (default 10000)
#
# Runs `/usr/bin/time -v liggghts -in in.settle` in OUTDIR and prints one line of key=value:
#   settle_loop_s / dense_loop_s     "Loop time of ..." (wall clock) of the two runs
#   *_pstep_per_s                    N*steps/loop time
#   *_cpu_s, *_cpu_pstep_per_s       CPU time (user+sys) of the process during each phase, sampled
#                                    from /proc at the phase boundaries (robust against other load
#                                    on the machine; equal to the loop time on an idle machine)
#   peak_rss_kb                      "Maximum resident set size" from time -v
#   load_before/load_after           1-min load average around the run
set -euo pipefail

if [ $# -lt 2 ]; then
    sed -n '2,17p' "$0" >&2
    exit 2
fi
N=$1; OUT=$2; SETTLE=${3:-50000}; DENSE=${4:-10000}
shift $(( $# < 4 ? $# : 4 ))
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
LIGGGHTS=${LIGGGHTS:-liggghts}
command -v "$LIGGGHTS" >/dev/null || { echo "liggghts not found (apt-get install -y liggghts)" >&2; exit 1; }

mkdir -p "$OUT"
python3 "$HERE/liggghts_input.py" -n "$N" -o "$OUT" --settle-steps "$SETTLE" --dense-steps "$DENSE" "$@" >/dev/null 2>&1

cd "$OUT"
export OMP_NUM_THREADS=1
exec python3 - "$N" "$SETTLE" "$DENSE" "$LIGGGHTS" <<'PY'
import os, re, subprocess, sys, time
n, settle, dense = (int(v) for v in sys.argv[1:4])
exe = sys.argv[4]
tick = os.sysconf("SC_CLK_TCK")

def load1():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])

def cpu_of(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            s = f.read()
        fields = s[s.rindex(")") + 2:].split()
        return (int(fields[11]) + int(fields[12])) / tick  # utime + stime
    except (OSError, ValueError, IndexError):
        return None

def child_of(pid):
    try:
        with open("/proc/%d/task/%d/children" % (pid, pid)) as f:
            c = f.read().split()
        return int(c[0]) if c else None
    except OSError:
        return None

load_before = load1()
with open("stdout.txt", "w") as so, open("time.txt", "w") as se:
    p = subprocess.Popen(["/usr/bin/time", "-v", exe, "-in", "in.settle", "-log", "log.liggghts"],
                         stdout=so, stderr=se)
    lig = None
    marks = {}          # name -> cpu seconds of the liggghts process
    last_cpu = 0.0
    step_re = {"settle_start": re.compile(r"^\s*0\s+\d+\s", re.M),
               "dense_start": re.compile(r"^\s*%d\s+%d\s" % (settle, n), re.M)}
    while p.poll() is None:
        time.sleep(0.1)
        if lig is None:
            lig = child_of(p.pid)
            continue
        c = cpu_of(lig)
        if c is not None:
            last_cpu = c
        try:
            with open("log.liggghts") as f:
                txt = f.read()
        except OSError:
            continue
        for name, rx in step_re.items():
            if name not in marks and rx.search(txt):
                marks[name] = last_cpu
load_after = load1()
if p.returncode != 0:
    sys.exit("liggghts failed (rc %d), see %s/stdout.txt and time.txt" % (p.returncode, os.getcwd()))

log = open("log.liggghts").read()
loops = [(float(t), int(s)) for t, s in re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", log)]
if len(loops) < 2:
    sys.exit("expected two 'Loop time' lines, found %d" % len(loops))
(ts, ss), (td, sd) = loops[-2], loops[-1]
tv = open("time.txt").read()
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", tv).group(1))
ut = float(re.search(r"User time \(seconds\): ([0-9.]+)", tv).group(1))
st = float(re.search(r"System time \(seconds\): ([0-9.]+)", tv).group(1))
m = re.search(r"Elapsed \(wall clock\) time.*?: (?:(\d+):)?(\d+):([0-9.]+)", tv)
wall = (int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3))) if m else float("nan")
total_cpu = ut + st
nan = float("nan")
c_settle = marks["dense_start"] - marks["settle_start"] if {"settle_start", "dense_start"} <= set(marks) else nan
c_dense = total_cpu - marks["dense_start"] if "dense_start" in marks else nan
rows = re.findall(r"^\s*(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", log, re.M)
ke, zmax = (rows[-1][2], rows[-1][5]) if rows else ("nan", "nan")
print("n=%d settle_steps=%d settle_loop_s=%.3f settle_pstep_per_s=%.4g settle_cpu_s=%.2f settle_cpu_pstep_per_s=%.4g "
      "dense_steps=%d dense_loop_s=%.3f dense_pstep_per_s=%.4g dense_cpu_s=%.2f dense_cpu_pstep_per_s=%.4g "
      "peak_rss_kb=%d wall_s=%.1f cpu_s=%.1f load_before=%.2f load_after=%.2f final_ke=%s final_zmax=%s"
      % (n, ss, ts, n * ss / ts, c_settle, n * ss / c_settle, sd, td, n * sd / td, c_dense, n * sd / c_dense,
         rss, wall, total_cpu, load_before, load_after, ke, zmax))
PY
