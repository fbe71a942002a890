#!/usr/bin/env python3
"""Side-by-side path tracing of the Cornell box: Irradia against Mitsuba 3.

Renders Mitsuba's `mi.cornell_box()` (512x512, max depth 8, box pixel filter so both
renderers reconstruct pixels the same way) with Mitsuba's scalar_rgb and llvm_ad_rgb
variants and Irradia's built-in `cornell` scene, interleaved, and reports:

  * speed: samples per second of each (median of the runs), and Irradia's ratios;
  * agreement: the mean radiance of each surface (walls, floor, ceiling, both boxes)
    in a high-sample render of each, using masks from Irradia's object-id image
    (eroded by 2 pixels so edges do not mix surfaces).

Usage: python3 bench/pathtrace/compare.py [--spp 64] [--runs 5] [--threads 2]
       [--agree-spp 1024] [--agree-res 256] [--skip-speed] [--skip-agree]
Installs Mitsuba with pip when it is missing; skips cleanly when it cannot.
"""
import argparse, json, os, statistics, subprocess, sys, tempfile, time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"


# The Mitsuba install, the binary, the PFM reader and the mask erosion are the reference
# script's (one of each in bench/pathtrace/).
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_reference import ensure_mitsuba, eroded_labels, irradia_binary, read_pfm  # noqa: E402


MITSUBA_CODE = r'''
import sys, time, json
import mitsuba as mi, drjit as dr, numpy as np
variant, spp, res, threads, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
t0 = time.perf_counter()
mi.set_variant(variant)
dr.set_thread_count(threads)
d = mi.cornell_box()
d["sensor"]["film"]["width"] = res
d["sensor"]["film"]["height"] = res
d["sensor"]["film"]["rfilter"] = {"type": "box"}
d["sensor"]["sampler"]["sample_count"] = spp
d["integrator"]["max_depth"] = 8
scene = mi.load_dict(d)
t1 = time.perf_counter()
img = np.array(mi.render(scene, spp=spp))
t2 = time.perf_counter()
if out != "-":
    np.save(out, img.astype(np.float32))
print(json.dumps({"render_s": t2 - t1, "total_s": t2 - t0}))
'''


def run_mitsuba(variant, spp, res, threads, out="-"):
    env = dict(os.environ)
    if variant.startswith("llvm"):
        env["DRJIT_LIBLLVM_PATH"] = LLVM
    r = subprocess.run([sys.executable, "-c", MITSUBA_CODE, variant, str(spp), str(res), str(threads), out],
                       capture_output=True, text=True, env=env)
    if r.returncode != 0:
        raise RuntimeError(f"mitsuba {variant} failed: {r.stderr[-2000:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def run_irradia(binary, spp, res, threads, out):
    t0 = time.perf_counter()
    subprocess.run([binary, "render", "--builtin", "cornell", "--spp", str(spp), "--width", str(res), "--height", str(res),
                    "--threads", str(threads), "--quiet", "-o", out], check=True)
    return time.perf_counter() - t0


def surface_masks(binary, res, tmp):
    """Object ids of Irradia's cornell scene (Whitted pass, 1 spp), eroded by 2 px."""
    import numpy as np
    out = os.path.join(tmp, "ids.pfm")
    subprocess.run([binary, "render", "--builtin", "cornell", "--integrator", "whitted", "--spp", "1", "--width", str(res),
                    "--height", str(res), "--quiet", "--aov", "object-id", "-o", out], check=True)
    ids = np.rint(read_pfm(os.path.join(tmp, "ids.object-id.pfm"))[..., 0]).astype(int)
    names = ["floor", "ceiling", "back wall", "red wall", "green wall", "light", "tall box", "short box"]
    labels = eroded_labels(ids, 2)  # eroded by 2 px; the image border counts as another surface
    masks = {n: labels == i for i, n in enumerate(names)}
    return masks


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--res", type=int, default=512)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--agree-spp", type=int, default=1024)
    ap.add_argument("--agree-res", type=int, default=256)
    ap.add_argument("--skip-speed", action="store_true")
    ap.add_argument("--skip-agree", action="store_true")
    a = ap.parse_args()
    if not ensure_mitsuba():
        return 0
    import numpy as np
    binary = irradia_binary()
    tmp = tempfile.mkdtemp()
    samples = a.res * a.res * a.spp
    if not a.skip_speed:
        times = {"irradia": [], "scalar_rgb": [], "llvm_ad_rgb": []}
        llvm_total = []
        for _ in range(a.runs):
            times["irradia"].append(run_irradia(binary, a.spp, a.res, a.threads, os.path.join(tmp, "i.pfm")))
            times["scalar_rgb"].append(run_mitsuba("scalar_rgb", a.spp, a.res, a.threads)["render_s"])
            r = run_mitsuba("llvm_ad_rgb", a.spp, a.res, a.threads)
            times["llvm_ad_rgb"].append(r["render_s"])
            llvm_total.append(r["total_s"])
        med = {k: statistics.median(v) for k, v in times.items()}
        print(f"speed ({a.res}x{a.res}, {a.spp} spp, max depth 8, {a.threads} threads, median of {a.runs}):")
        for k, v in med.items():
            print(f"  {k:12s} {v:7.2f} s  {samples / v / 1e6:6.2f} Msamples/s   runs {['%.2f' % x for x in times[k]]}")
        print(f"  Irradia whole process; Mitsuba render call (scene already loaded, JIT included for llvm)")
        print(f"  ratio Irradia/llvm_ad_rgb samples/s: {med['llvm_ad_rgb'] / med['irradia']:.2f} (goal >= 1)")
        print(f"  ratio Irradia/scalar_rgb samples/s:  {med['scalar_rgb'] / med['irradia']:.2f} (goal >= 3)")
    if not a.skip_agree:
        res, spp = a.agree_res, a.agree_spp
        out = os.path.join(tmp, "agree.pfm")
        run_irradia(binary, spp, res, a.threads, out)
        ours = read_pfm(out)
        mts_path = os.path.join(tmp, "mts.npy")
        run_mitsuba("llvm_ad_rgb", spp, res, a.threads, mts_path)
        theirs = np.load(mts_path)[..., :3]
        masks = surface_masks(binary, res, tmp)
        print(f"agreement ({res}x{res}, {spp} spp each): mean radiance per surface")
        worst = 0.0
        for n, m in masks.items():
            if n == "light" or m.sum() == 0:
                continue
            o = ours[m].mean(axis=0)
            t = theirs[m].mean(axis=0)
            rel = np.abs(o - t) / np.maximum(t, 1e-6)
            lum = lambda c: 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
            rl = abs(lum(o) - lum(t)) / lum(t)
            worst = max(worst, rl)
            print(f"  {n:11s} px {int(m.sum()):6d}  irradia {np.round(o, 4)}  mitsuba {np.round(t, 4)}  "
                  f"rel diff per channel {np.round(rel * 100, 2)} %  luminance {rl * 100:.2f} %")
        print(f"  worst luminance difference {worst * 100:.2f} % (goal < 1 %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
