#!/usr/bin/env bash
# Interleaved A/B of two raster_bench binaries by CPU time (perf stat task-clock of the
# whole process: load + 1 warm-up + FRAMES frames), which the other processes of a
# loaded machine disturb less than wall time. Prints medians and the ratio B/A.
#
#   bench/raster/ab_cpu.sh BIN_A BIN_B WORKLOAD.bin [ROUNDS=7] [FRAMES=4] [THREADS=1]
set -euo pipefail
A=$1; B=$2; W=$3; ROUNDS=${4:-7}; FRAMES=${5:-4}; THREADS=${6:-1}
echo "load before: $(uptime)"
for r in $(seq 1 "$ROUNDS"); do
    for bin in "$A" "$B"; do
        ms=$(perf stat -x, -e task-clock "$bin" time "$W" "$FRAMES" "$THREADS" 2>&1 >/dev/null | grep task-clock | cut -d, -f1)
        echo "$bin $ms"
    done
done | python3 -c '
import sys, statistics
runs = {}
for line in sys.stdin:
    b, t = line.split()
    runs.setdefault(b, []).append(float(t))
(a, ta), (b, tb) = list(runs.items())
for name, t in [(a, ta), (b, tb)]:
    print(f"{name}: median {statistics.median(t):.0f} ms CPU, min {min(t):.0f}, runs {len(t)}")
print(f"B/A: median {statistics.median(tb) / statistics.median(ta):.3f}, min {min(tb) / min(ta):.3f}")
'
echo "load after: $(uptime)"
