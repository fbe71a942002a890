#!/usr/bin/env python3
"""Two builds of triangles_bench compared phase by phase, in interleaved pairs.

    python3 bench/triangles/phase_pairs.py N BIN_A BIN_B DIR

Runs `BIN run DIR` A B B A A B ... (N pairs, the order alternating), each pinned to
CPU 1 with RAYON_NUM_THREADS=1, reads the CPU seconds the bench reports per phase
(`cpu_s`: BVH build alone, whole mesh build, primary, incoherent) and prints, per
phase, both medians and the median and range of the pair-by-pair ratios B/A. CPU
seconds of one pinned process are what a shared machine still lets one compare.
"""
import json, os, statistics, subprocess, sys

n, a, b, d = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
env = dict(os.environ, RAYON_NUM_THREADS="1")
res = {a: [], b: []}


def run(binp):
    out = subprocess.run(["taskset", "-c", "1", binp, "run", d], env=env,
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


print("load", open("/proc/loadavg").read().split()[:3], flush=True)
for i in range(n):
    for binp in ((a, b) if i % 2 == 0 else (b, a)):
        j = run(binp)
        res[binp].append(j)
        print(binp.split('/')[-1], j["cpu_s"], j["primary_hits"], j["incoherent_hits"], flush=True)
print("load", open("/proc/loadavg").read().split()[:3])
for ph in ["bvh_build", "build", "primary", "incoherent"]:
    A = [r["cpu_s"][ph] for r in res[a]]
    B = [r["cpu_s"][ph] for r in res[b]]
    ratios = sorted(y / x for x, y in zip(A, B))
    print(f"{ph:11s} A {statistics.median(A):.3f}  B {statistics.median(B):.3f}  "
          f"B/A median of pairs {statistics.median(ratios):.3f}  range {ratios[0]:.3f}-{ratios[-1]:.3f}")
