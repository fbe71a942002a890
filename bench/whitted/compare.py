#!/usr/bin/env python3
"""Side-by-side wall time and PSNR of Irradia and POV-Ray on one scene.

Usage: compare.py IRRADIA_BIN BUILTIN POV_FILE [--runs N] [--threads 1,2]

Each measurement is one hyperfine run (whole process, `-N`, no shell), and the runs are
interleaved A B A B so machine load hits both alike. Prints medians, the ratio
Irradia / POV-Ray per thread count, the PSNR of Irradia's PNG against POV-Ray's, and the
load average, as a Markdown table.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image


def psnr(a_path, b_path):
    a = np.asarray(Image.open(a_path).convert("RGB"), dtype=np.float64)
    b = np.asarray(Image.open(b_path).convert("RGB"), dtype=np.float64)
    if a.shape != b.shape:
        sys.exit(f"image sizes differ: {a.shape} vs {b.shape}")
    mse = np.mean((a - b) ** 2)
    return float("inf") if mse == 0 else 10 * np.log10(255.0**2 / mse)


def one_run(command, tmp):
    out = os.path.join(tmp, "h.json")
    subprocess.run(
        ["hyperfine", "-N", "--runs", "1", "--style", "none", "--export-json", out, command],
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    with open(out) as f:
        r = json.load(f)["results"][0]
    # Wall time, and CPU time (user + system) which machine load distorts far less.
    return r["times"][0], r["user"] + r["system"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("irradia")
    ap.add_argument("builtin")
    ap.add_argument("pov")
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=720)
    args = ap.parse_args()

    tmp = tempfile.mkdtemp(prefix="irradia-bench-")
    irr_png = os.path.join(tmp, "irradia.png")
    pov_png = os.path.join(tmp, "povray.png")
    rows = []
    cpu_rows = []
    load_before = os.getloadavg()
    for t in [int(x) for x in args.threads.split(",")]:
        cmds = {
            "povray": f"povray +W{args.width} +H{args.height} -A +WT{t} -D -V -GA "
            f"+I{args.pov} +O{pov_png}",
            "irradia": f"{args.irradia} render --builtin {args.builtin} --threads {t} "
            f"--width {args.width} --height {args.height} --quiet -o {irr_png}",
        }
        times = {k: [] for k in cmds}
        cpu = {k: [] for k in cmds}
        for _ in range(args.runs):
            for name, cmd in cmds.items():
                wall, c = one_run(cmd, tmp)
                times[name].append(wall)
                cpu[name].append(c)
        med = {k: statistics.median(v) for k, v in times.items()}
        cmed = {k: statistics.median(v) for k, v in cpu.items()}
        rows.append((t, med["povray"], med["irradia"], med["irradia"] / med["povray"], times))
        cpu_rows.append((t, cmed["povray"], cmed["irradia"], cmed["irradia"] / cmed["povray"]))
    load_after = os.getloadavg()
    quality = psnr(irr_png, pov_png)

    print(f"scene {args.builtin} {args.width}x{args.height}, {args.runs} interleaved runs each")
    print(f"load average before {load_before[0]:.2f}, after {load_after[0]:.2f}")
    print()
    print("| threads | POV-Ray median (s) | Irradia median (s) | Irradia / POV-Ray |")
    print("|---|---|---|---|")
    for t, p, i, r, _ in rows:
        print(f"| {t} | {p:.3f} | {i:.3f} | {r:.3f} |")
    print()
    print("| threads | POV-Ray CPU median (s) | Irradia CPU median (s) | Irradia / POV-Ray (CPU) |")
    print("|---|---|---|---|")
    for t, p, i, r in cpu_rows:
        print(f"| {t} | {p:.3f} | {i:.3f} | {r:.3f} |")
    print()
    print(f"PSNR Irradia vs POV-Ray: {quality:.2f} dB")
    for t, _, _, _, times in rows:
        for k, v in times.items():
            print(f"  raw {k} {t} thread(s): " + " ".join(f"{x:.3f}" for x in v))
    goal_time = all(r <= 0.2 for _, _, _, r, _ in rows)
    print(f"goal (ratio <= 0.2 at every thread count, issue 14 goal 3): {'met' if goal_time else 'NOT met'}")
    print(f"goal (PSNR >= 30 dB): {'met' if quality >= 30 else 'NOT met'}")


if __name__ == "__main__":
    main()
