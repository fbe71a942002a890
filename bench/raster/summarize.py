#!/usr/bin/env python3
"""Summarises bench/raster/run.sh: medians, ratios and image differences (markdown)."""
import json
import statistics
import sys

import numpy as np
from PIL import Image

results, out = sys.argv[1], sys.argv[2]
rows = [json.loads(l) for l in open(results) if l.strip()]
print("| workload | threads | Irradia s/frame | llvmpipe s/frame | ratio | runs | differing pixels |")
print("|---|---|---|---|---|---|---|")
for w in ["random", "gyroid"]:
    for t in sorted({r["threads"] for r in rows if r["workload"] == w}):
        med = {}
        n = 0
        for name in ["irradia", "llvmpipe"]:
            runs = [r["median_s"] for r in rows if r["workload"] == w and r["threads"] == t and r["renderer"] == name]
            med[name] = statistics.median(runs) if runs else float("nan")
            n = len(runs)
        try:
            a = np.asarray(Image.open(f"{out}/irradia-{w}-{t}.png").convert("RGB")).astype(int)
            b = np.asarray(Image.open(f"{out}/llvmpipe-{w}-{t}.png").convert("RGB")).astype(int)
            d = np.abs(a - b).max(axis=2)
            diff = f"{(d > 0).mean() * 100:.3f}% (>2 levels: {(d > 2).mean() * 100:.3f}%)"
        except FileNotFoundError:
            diff = "n/a"
        print(f"| {w} | {t} | {med['irradia']:.3f} | {med['llvmpipe']:.3f} | {med['irradia'] / med['llvmpipe']:.2f} | {n} | {diff} |")
