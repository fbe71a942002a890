#!/usr/bin/env python3
"""Pairwise ratios from two JSON-line logs written by interleaved runs (A B A B ...).

    python3 bench/triangles/pair_ratios.py A.log B.log

Each log holds one JSON line per run (triangles_bench run / embree_bench.py, or
o3d_bench.py); the warm-up runs come first and are dropped (--warmup, default 1).
Prints, per phase, the median of A's and B's own figures and the median of the
pairwise ratios A/B of rays per second (higher is better for A) and of build seconds.
"""
import json, statistics, sys

def rows(path, warmup):
    out = []
    for line in open(path):
        line = line.strip()
        if line.startswith("{"):
            out.append(json.loads(line))
    return out[warmup:]

def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    warmup = 1
    for a in sys.argv[1:]:
        if a.startswith("--warmup="):
            warmup = int(a.split("=")[1])
    a, b = rows(args[0], warmup), rows(args[1], warmup)
    n = min(len(a), len(b))
    a, b = a[:n], b[:n]
    print(f"{n} pairs")
    for k in ["primary", "incoherent"]:
        ra = [x[f"{k}_mrays"] for x in a]
        rb = [x[f"{k}_mrays"] for x in b]
        ratio = [x / y for x, y in zip(ra, rb)]
        ca = [x["cpu_s"][k] for x in a]
        cb = [x["cpu_s"][k] for x in b]
        cr = [y / x for x, y in zip(ca, cb) if x > 0]
        print(f"{k}: A {statistics.median(ra):.3f} B {statistics.median(rb):.3f} Mrays/s wall; "
              f"A/B speed median {statistics.median(ratio):.3f} (min {min(ratio):.3f} max {max(ratio):.3f}); "
              f"CPU s A {statistics.median(ca):.3f} B {statistics.median(cb):.3f}, B/A {statistics.median(cr):.3f}")
    ka = "mesh_build_s" if "mesh_build_s" in a[0] else "build_s"
    kb = "mesh_build_s" if "mesh_build_s" in b[0] else "build_s"
    ba = [x[ka] for x in a]
    bb = [x[kb] for x in b]
    r = [x / y for x, y in zip(ba, bb)]
    print(f"build: A {statistics.median(ba):.3f} s B {statistics.median(bb):.3f} s; A/B time median {statistics.median(r):.3f} "
          f"(min {min(r):.3f} max {max(r):.3f})")

main()
