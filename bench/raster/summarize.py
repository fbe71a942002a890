#!/usr/bin/env python3
"""Summarises bench/raster/run.sh: medians, ratios and image differences (markdown)."""
import json
import statistics
import sys

import numpy as np
from PIL import Image

results, out = sys.argv[1], sys.argv[2]
rows = [json.loads(l) for l in open(results) if l.strip()]
print("| workload | threads | pinned | Irradia s/frame | llvmpipe s/frame | ratio | CPU/wall Irradia, llvmpipe | runs | differing pixels |")
print("|---|---|---|---|---|---|---|---|---|")
for w in ["random", "gyroid"]:
    for t in sorted({r["threads"] for r in rows if r["workload"] == w}):
        med = {}
        cores = {}  # CPU time per frame over wall time per frame: the cores a program kept busy
        n = 0
        pinned = any(r.get("pinned") for r in rows if r["workload"] == w and r["threads"] == t)
        for name in ["irradia", "llvmpipe"]:
            mine = [r for r in rows if r["workload"] == w and r["threads"] == t and r["renderer"] == name]
            runs = [r["median_s"] for r in mine]
            med[name] = statistics.median(runs) if runs else float("nan")
            cpu = [r["cpu_median_s"] / r["median_s"] for r in mine if "cpu_median_s" in r]
            cores[name] = f"{statistics.median(cpu):.2f}" if cpu else "n/a"
            n = len(runs)
        try:
            a = np.asarray(Image.open(f"{out}/irradia-{w}-{t}.png").convert("RGB")).astype(int)
            b = np.asarray(Image.open(f"{out}/llvmpipe-{w}-{t}.png").convert("RGB")).astype(int)
            d = np.abs(a - b).max(axis=2)
            diff = f"{(d > 0).mean() * 100:.3f}% (>2 levels: {(d > 2).mean() * 100:.3f}%)"
        except FileNotFoundError:
            diff = "n/a"
        print(f"| {w} | {t} | {'one core' if pinned else 'no'} | {med['irradia']:.3f} | {med['llvmpipe']:.3f} | "
              f"{med['irradia'] / med['llvmpipe']:.3f} | {cores['irradia']}, {cores['llvmpipe']} | {n} | {diff} |")
