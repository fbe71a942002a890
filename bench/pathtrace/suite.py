#!/usr/bin/env python3
"""The path-tracing speed suite of issue 14 goal 1: Irradia against Mitsuba 3's
`scalar_rgb` and `llvm_ad_rgb` on the same scene files, at the same samples per pixel,
threads and maximum depth, timed as whole processes, with the noise of each.

The scenes are Mitsuba 3 XML files in bench/pathtrace/suite/ (Irradia renders them
through its Mitsuba importer, so both read the very same file):

  cornell       Mitsuba's mi.cornell_box()
  bunny         the Stanford bunny (Mitsuba's common/meshes/bunny.ply) in the box
  glass_mirror  a glass and a mirror sphere in the box
  rough_balls   rough conductor, rough dielectric and rough plastic balls under museum.exr
  veach_mis     glossy plates and lights of four sizes (Veach's MIS figure)

For every scene each renderer renders SEEDS independent images (sampler seeds 0..S-1,
renderers interleaved seed by seed, after one warm-up render each: Mitsuba's llvm
variant compiles its kernels then). Reported per scene and renderer:

  time        the median whole-process wall time of a render (and CPU time), so Mitsuba's
              Python start-up, scene loading and kernel compilation count as Irradia's
              process start, scene loading and BVH build do;
  variance    the per-pixel variance of one render, estimated from the spread of the S
              renders (unbiased, averaged over pixels and RGB);
  efficiency  1 / (variance x time): the figure that decides at equal quality;
  mean        the image's mean radiance (the renderers must agree: a sanity check that
              both drew the same scene, within the noise).

and the ratios Irradia / Mitsuba: speed (the peer's time over Irradia's) and efficiency.

Usage: python3 bench/pathtrace/suite.py [--scenes cornell bunny ...] [--spp 64]
       [--res 512] [--seeds 3] [--threads 2] [--variants scalar_rgb llvm_ad_rgb]
       [--json OUT]
(IRRADIA_BIN=PATH times that binary, e.g. a copy of another build, instead of building.)
Installs Mitsuba with pip when it is missing; skips cleanly (exit 0) when it cannot or
when Mitsuba's test data (../shared/mitsuba-data/common) is not there.
"""
import argparse, json, os, statistics, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SUITE = os.path.join(HERE, "suite")
SCENES = ["cornell", "bunny", "glass_mirror", "rough_balls", "veach_mis"]
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
from mitsuba_reference import ensure_mitsuba, irradia_binary, read_pfm  # noqa: E402
from pairs import run as timed  # noqa: E402

MITSUBA = r'''
import sys, json
import mitsuba as mi, drjit as dr, numpy as np
variant, xml, threads, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
params = json.loads(sys.argv[5])
mi.set_variant(variant)
dr.set_thread_count(threads)
scene = mi.load_file(xml, **params)
img = mi.render(scene, spp=int(params["spp"]), seed=int(params["seed"]))
np.save(out, np.array(img, dtype=np.float32)[:, :, :3])
'''


def declared(xml):
    """The parameters a scene file declares with <default name=...>."""
    import re
    return set(re.findall(r'<default\s+name="([^"]+)"', open(xml).read()))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", nargs="+", default=SCENES, choices=SCENES)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--res", type=int, default=512)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--variants", nargs="+", default=["scalar_rgb", "llvm_ad_rgb"])
    ap.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "mitsuba-data", "common"))
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args()
    if args.seeds < 2:
        sys.exit("--seeds must be at least 2 (the variance comes from their spread)")
    data = os.path.abspath(args.data)
    if not os.path.isfile(os.path.join(data, "meshes", "bunny.ply")):
        print(f"SKIP: Mitsuba's test data is not at {data} (--data)")
        return
    if not ensure_mitsuba():
        return
    import numpy as np
    irr = irradia_binary()
    env = dict(os.environ)
    if any(v.startswith("llvm") for v in args.variants) and not os.path.exists(LLVM):
        # Dr.Jit's LLVM back end aborts with Debian's default LLVM 14/15 (PEERS.md).
        print("installing libllvm19 for Mitsuba's llvm variants ...", flush=True)
        subprocess.run("apt-get install -y libllvm19 || (apt-get update && apt-get install -y libllvm19)",
                       shell=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if os.path.exists(LLVM):
        env.setdefault("DRJIT_LIBLLVM_PATH", LLVM)
    else:
        skipped = [v for v in args.variants if v.startswith("llvm")]
        if skipped:
            print(f"SKIP {skipped}: {LLVM} is missing (apt-get install libllvm19)", flush=True)
        args.variants = [v for v in args.variants if not v.startswith("llvm")]
    os.environ.update(env)
    print(f"load {open('/proc/loadavg').read().split()[:3]}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {args.res}x{args.res}, "
          f"{args.spp} spp, {args.threads} threads, {args.seeds} seeds", flush=True)
    renderers = ["irradia"] + args.variants
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes:
            xml = os.path.join(SUITE, scene + ".xml")
            want = declared(xml)

            def params(seed):
                p = {"spp": args.spp, "res": args.res, "seed": seed, "data": data}
                return {k: str(v) for k, v in p.items() if k in want}

            def render(r, seed):
                p = params(seed)
                if r == "irradia":
                    out = os.path.join(tmp, f"{scene}_{r}_{seed}.pfm")
                    cmd = [irr, "render", xml, "--threads", str(args.threads), "--quiet", "-o", out]
                    for k, v in p.items():
                        cmd += ["-D", f"{k}={v}"]
                    t = timed(cmd)
                    return t, read_pfm(out)
                out = os.path.join(tmp, f"{scene}_{r}_{seed}.npy")
                t = timed([sys.executable, "-c", MITSUBA, r, xml, str(args.threads), out, json.dumps(p)])
                return t, np.load(out)

            for r in renderers:  # warm-up (kernel compilation, file caches)
                render(r, 1000)
            runs = {r: [] for r in renderers}
            for seed in range(args.seeds):
                order = renderers[seed % len(renderers):] + renderers[:seed % len(renderers)]
                for r in order:
                    runs[r].append(render(r, seed))
            row = {}
            for r in renderers:
                imgs = np.stack([img.astype(np.float64) for _, img in runs[r]])
                var = float(imgs.var(axis=0, ddof=1).mean())
                wall = statistics.median(t["wall"] for t, _ in runs[r])
                cpu = statistics.median(t["cpu"] for t, _ in runs[r])
                row[r] = {"wall_s": wall, "cpu_s": cpu, "variance": var,
                          "efficiency": 1.0 / (var * wall) if var > 0 else float("inf"),
                          "mean": float(imgs.mean())}
            results[scene] = row
            print(f"\n## {scene}")
            print("| renderer | wall s | CPU s | variance | efficiency | mean radiance |")
            print("|---|---|---|---|---|---|")
            for r in renderers:
                x = row[r]
                print(f"| {r} | {x['wall_s']:.2f} | {x['cpu_s']:.2f} | {x['variance']:.4g} | "
                      f"{x['efficiency']:.4g} | {x['mean']:.4f} |")
            for v in args.variants:
                a, b = row["irradia"], row[v]
                print(f"Irradia / {v}: speed {b['wall_s'] / a['wall_s']:.2f}x, "
                      f"efficiency {a['efficiency'] / b['efficiency']:.2f}x, "
                      f"variance {a['variance'] / b['variance']:.2f}, "
                      f"mean {a['mean'] / b['mean'] - 1:+.2%}", flush=True)
    print("\n## summary (Irradia / peer; goal: speed and efficiency >= 1.5 vs llvm_ad_rgb, "
          "speed >= 4 vs scalar_rgb)")
    print("| scene | " + " | ".join(f"speed vs {v} | efficiency vs {v}" for v in args.variants) + " |")
    print("|---" * (1 + 2 * len(args.variants)) + "|")
    for scene, row in results.items():
        a = row["irradia"]
        cells = []
        for v in args.variants:
            b = row[v]
            cells += [f"{b['wall_s'] / a['wall_s']:.2f}", f"{a['efficiency'] / b['efficiency']:.2f}"]
        print(f"| {scene} | " + " | ".join(cells) + " |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "results": results}, f, indent=1)


if __name__ == "__main__":
    main()
