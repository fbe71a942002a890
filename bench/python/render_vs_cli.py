#!/usr/bin/env python3
"""Scene.render against `irradia render` on the same image, interleaved A B A B.

    python bench/python/render_vs_cli.py --cli target/release/irradia [--rounds 7]
        [--case cornell:64x64:4 --case whitted:160x90 ...]

Cases are NAME:WIDTHxHEIGHT[:SPP] of `irradia.builtin` scenes (default: the three
below); small images expose the fixed cost of a call (scene conversion, thread start,
the array). Within each round the two sides run in alternating order (CLI first in
odd rounds, Python first in even ones), so neither always runs second on a warmed
cache.

For each case: the render time each reports (the driver's own clock: `Rendered ...
in X s` / `Scene.last_render["seconds"]`) and the wall time of the call (the CLI as a
whole process, scene loading and writing the PFM included; Python: load + render in a
running interpreter) and the CPU time of the call (the CLI process's user + system
time from getrusage; Python's process time over load + render + array, all threads):
CPU time is what the load of a shared machine disturbs least. Prints medians and the
median of the pairwise ratios python/cli. Checks the images are equal. The binding's
own cost is the wall time of `scene.render()` minus the driver's clock (binding_ms;
binding_share: its share of the call)."""

import argparse
import re
import resource
import statistics
import subprocess
import tempfile
import time

import numpy as np

import irradia

CASES = [
    ("whitted", dict(width=1280, height=720), []),
    ("cornell", dict(width=256, height=256, spp=16), []),
    ("csg", dict(width=640, height=360), []),
]


def parse_case(text):
    """NAME:WIDTHxHEIGHT[:SPP] as a CASES entry."""
    parts = text.split(":")
    w, h = (int(x) for x in parts[1].split("x"))
    kw = dict(width=w, height=h)
    if len(parts) > 2:
        kw["spp"] = int(parts[2])
    return parts[0], kw, []


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", required=True)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--case", action="append", default=[], help="NAME:WxH[:SPP], repeatable")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    cases = [parse_case(c) for c in a.case] or CASES
    for name, kw, _ in cases:
        flags = [x for k, v in kw.items() for x in ("--" + k, str(v))]
        cmd = [a.cli, "render", "--builtin", name, *flags, "--threads", str(a.threads), "-o", tmp + "/x.pfm"]
        rows = []
        for r in range(a.rounds + 1):  # round 0 warms up
            def cli():
                ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
                t0 = time.perf_counter()
                p = subprocess.run(cmd, capture_output=True, text=True, check=True)
                wall = time.perf_counter() - t0
                ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)
                m = re.search(r"in ([0-9.]+) s", p.stderr)
                return float(m.group(1)), wall, cpu

            def py():
                c0 = time.process_time()
                t0 = time.perf_counter()
                s = irradia.builtin(name)
                t1 = time.perf_counter()
                img = s.render(threads=a.threads, **kw)
                call = time.perf_counter() - t1
                wall = time.perf_counter() - t0
                cpu = time.process_time() - c0
                return img, s.last_render["seconds"], wall, cpu, call

            if r % 2:
                cli_render, cli_wall, cli_cpu = cli()
                img, py_render, py_wall, py_cpu, py_call = py()
            else:
                img, py_render, py_wall, py_cpu, py_call = py()
                cli_render, cli_wall, cli_cpu = cli()
            if r == 0:
                assert np.array_equal(img, irradia.read_image(tmp + "/x.pfm")), "images differ"
                continue
            rows.append((cli_render, py_render, cli_wall, py_wall, cli_cpu, py_cpu, py_call - py_render, py_call))
        med = lambda i: statistics.median(x[i] for x in rows)
        ratio = lambda i, j: statistics.median(x[j] / x[i] for x in rows)
        print(f"RESULT case={name} {' '.join(f'{k}={v}' for k, v in kw.items())} threads={a.threads} "
              f"cli_render_s={med(0):.4f} py_render_s={med(1):.4f} render_ratio={ratio(0, 1):.4f} "
              f"cli_wall_s={med(2):.4f} py_wall_s={med(3):.4f} wall_ratio={ratio(2, 3):.4f} "
              f"cli_cpu_s={med(4):.4f} py_cpu_s={med(5):.4f} cpu_ratio={ratio(4, 5):.4f} "
              f"binding_ms={1e3 * med(6):.2f} binding_share={statistics.median(x[6] / x[7] for x in rows):.4f} "
              f"render_ratio_min={min(x[1] / x[0] for x in rows):.4f} render_ratio_max={max(x[1] / x[0] for x in rows):.4f}")


if __name__ == "__main__":
    main()
