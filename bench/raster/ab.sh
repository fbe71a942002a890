#!/usr/bin/env bash
# Interleaved A/B timing of two raster_bench binaries (A B A B ...) on one workload,
# for comparing two builds of the rasterizer on a loaded machine: prints the median
# and minimum over the runs of each binary's per-run median frame time.
#
#   bench/raster/ab.sh BIN_A BIN_B WORKLOAD.bin [ROUNDS=7] [FRAMES=3] [THREADS=1]
set -euo pipefail
A=$1; B=$2; W=$3; ROUNDS=${4:-7}; FRAMES=${5:-3}; THREADS=${6:-1}
echo "load before: $(uptime)"
for r in $(seq 1 "$ROUNDS"); do
    for bin in "$A" "$B"; do
        printf '%s ' "$bin"
        "$bin" time "$W" "$FRAMES" "$THREADS" 2>/dev/null | sed -n 's/.*"median_s":\([0-9.]*\).*/\1/p'
    done
done | python3 -c '
import sys, statistics
runs = {}
for line in sys.stdin:
    b, t = line.split()
    runs.setdefault(b, []).append(float(t))
(a, ta), (b, tb) = list(runs.items())
for name, t in [(a, ta), (b, tb)]:
    print(f"{name}: median {statistics.median(t):.4f} s/frame, min {min(t):.4f}, runs {len(t)}")
print(f"B/A: median {statistics.median(tb) / statistics.median(ta):.3f}, min {min(tb) / min(ta):.3f}")
'
echo "load after: $(uptime)"
