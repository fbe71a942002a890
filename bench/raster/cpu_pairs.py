#!/usr/bin/env python3
"""Per-frame CPU time of two raster_bench binaries, interleaved in pairs (A B A B ...).

    python3 bench/raster/cpu_pairs.py ROUNDS FRAMES THREADS WORKLOAD.bin BIN_A BIN_B

Each run prints cpu_median_s (the median over FRAMES frames of the process CPU time per
frame, after one warm-up frame: loading the workload is left out); prints the medians
and the median and range of the pair ratios A/B, with the load average before and after.
"""
import json, subprocess, sys, statistics, os
r, f, t, w, a, b = sys.argv[1:7]
print("load", open('/proc/loadavg').read().split()[:3])
ra, rb, wa, wb = [], [], [], []
for i in range(int(r)):
    for name, lst, wl in ((a, ra, wa), (b, rb, wb)):
        out = subprocess.run([name, "time", w, f, t], capture_output=True, text=True).stdout
        j = json.loads(out.strip().splitlines()[-1])
        lst.append(j["cpu_median_s"]); wl.append(j["median_s"])
ratios = [x / y for x, y in zip(ra, rb)]
print(f"A cpu/frame median {statistics.median(ra):.4f}  B {statistics.median(rb):.4f}  A/B pairs median {statistics.median(ratios):.3f} range {min(ratios):.3f}-{max(ratios):.3f}")
print(f"A wall/frame median {statistics.median(wa):.4f}  B {statistics.median(wb):.4f}")
print("load", open('/proc/loadavg').read().split()[:3])
