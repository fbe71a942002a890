#!/usr/bin/env bash
# Interleaved A/B timing of two raster_bench binaries (A B A B ...) on one workload,
# for comparing two builds of the rasterizer on a loaded machine. Prints the median and
# minimum of each binary's runs and the ratio B/A.
#
#   bench/raster/ab.sh BIN_A BIN_B WORKLOAD.bin [ROUNDS=7] [FRAMES=3] [THREADS=1]
#
# CLOCK=wall (default): each run's median frame time. CLOCK=cpu: the whole process's
# CPU time (perf stat task-clock: load + 1 warm-up + FRAMES frames), which the other
# processes of a loaded machine disturb less than wall time.
set -euo pipefail
A=$1; B=$2; W=$3; ROUNDS=${4:-7}; FRAMES=${5:-3}; THREADS=${6:-1}
CLOCK=${CLOCK:-wall}
case "$CLOCK" in wall|cpu) ;; *) echo "CLOCK=$CLOCK: expected wall or cpu" >&2; exit 2;; esac
echo "load before: $(uptime)"
for r in $(seq 1 "$ROUNDS"); do
    for bin in "$A" "$B"; do
        if [ "$CLOCK" = cpu ]; then
            t=$(perf stat -x, -e task-clock "$bin" time "$W" "$FRAMES" "$THREADS" 2>&1 >/dev/null | grep task-clock | cut -d, -f1)
        else
            t=$("$bin" time "$W" "$FRAMES" "$THREADS" 2>/dev/null | sed -n 's/.*"median_s":\([0-9.]*\).*/\1/p')
        fi
        echo "$bin $t"
    done
done | CLOCK=$CLOCK python3 -c '
import os, sys, statistics
runs = {}
for line in sys.stdin:
    b, t = line.split()
    runs.setdefault(b, []).append(float(t))
(a, ta), (b, tb) = list(runs.items())
unit = "ms CPU" if os.environ["CLOCK"] == "cpu" else "s/frame"
for name, t in [(a, ta), (b, tb)]:
    print(f"{name}: median {statistics.median(t):.4f} {unit}, min {min(t):.4f}, runs {len(t)}")
print(f"B/A: median {statistics.median(tb) / statistics.median(ta):.3f}, min {min(tb) / min(ta):.3f}")
'
echo "load after: $(uptime)"
