#!/usr/bin/env python3
"""The triangles workload of PEERS.md: Irradia's BVH against Embree 4 (embreex) at 1
thread and Open3D 0.20's RaycastingScene (Embree inside, multi-threaded) at 2 or more.

    python3 bench/triangles/run.py [--runs 5] [--threads 1 2] [--data DIR]

embreex traces with one rtcIntersect1 per ray in a single-threaded loop, so it is the
per-thread anchor only: at N > 1 threads the peer is Open3D (`o3d_bench.py DIR N`,
nthreads=N), never single-threaded Embree against N Irradia threads.

1. Builds `crates/geometry/examples/triangles_bench.rs` (release) and writes the gyroid
   (marching cubes, 342^3) and both ray sets once, as raw arrays, to DIR.
2. For each thread count N, runs Irradia and the peer alternately (A B A B ...), RUNS
   times each, every process pinned to N cores with `taskset` (Irradia also gets
   RAYON_NUM_THREADS=N; embreex does not expose Embree's thread count, so the pinning
   is what limits its TBB build threads).
3. Prints medians, ratios and the hit-count check (must agree within 0.01%).
"""
import argparse, json, os, shutil, statistics, subprocess, sys, time
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run_json(cmd, env=None):
    out = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--data", default=os.path.join(ROOT, "target", "bench-triangles"))
    args = ap.parse_args()
    try:
        import open3d  # noqa: F401
    except ImportError:
        print("open3d missing: trying pip install open3d-cpu==0.20.0", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "pip", "install", "open3d-cpu==0.20.0"])
    try:
        import embreex  # noqa: F401
    except ImportError:
        print("embreex missing: trying pip install embreex==4.4.0.post1", file=sys.stderr)
        if subprocess.run([sys.executable, "-m", "pip", "install", "embreex==4.4.0.post1"]).returncode:
            print("SKIP: Embree (embreex) cannot be installed here")
            return
    env = dict(os.environ)
    target = env.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    subprocess.run(["cargo", "build", "--release", "-p", "irradia-geometry", "--example", "triangles_bench"],
                   cwd=ROOT, check=True)
    exe = os.path.join(target, "release", "examples", "triangles_bench")
    if not os.path.exists(os.path.join(args.data, "incoherent_dir.f32")):
        subprocess.run([exe, "write", args.data], check=True)
    ncpu = os.cpu_count() or 1
    taskset = shutil.which("taskset")
    results = {}
    for n in args.threads:
        pin = [taskset, "-c", ",".join(str(i) for i in range(min(n, ncpu)))] if taskset else []
        e = dict(env, RAYON_NUM_THREADS=str(n))
        ir, em = [], []
        for r in range(args.runs):
            ir.append(run_json(pin + [exe, "run", args.data], e))
            peer = ["embree_bench.py", args.data] if n == 1 else ["o3d_bench.py", args.data, str(n)]
            em.append(run_json(pin + [sys.executable, os.path.join(HERE, peer[0])] + peer[1:], e))
            print(f"threads {n} run {r + 1}: irradia build {ir[-1]['mesh_build_s']:.3f}s "
                  f"primary {ir[-1]['primary_mrays']:.2f} incoherent {ir[-1]['incoherent_mrays']:.2f} | "
                  f"{em[-1]['renderer']} build {em[-1]['build_s']:.3f}s primary {em[-1]['primary_mrays']:.2f} "
                  f"incoherent {em[-1]['incoherent_mrays']:.2f}", flush=True)
        results[n] = (ir, em)
    # Hit agreement (the last runs wrote their hit distances).
    d = args.data
    agree = {}
    last_peer = results[args.threads[-1]][1][-1]["renderer"]
    for s in ["primary", "incoherent"]:
        a = np.fromfile(os.path.join(d, f"{s}_t_irradia.f32"), dtype="<f4")
        b = np.fromfile(os.path.join(d, f"{s}_t_{last_peer}.f32"), dtype="<f4")
        ha, hb = np.isfinite(a), np.isfinite(b)
        both = ha & hb
        rel = np.abs(a[both] - b[both]) / np.maximum(np.abs(b[both]), 1e-30)
        agree[s] = dict(irradia=int(ha.sum()), embree=int(hb.sum()),
                        diff_pct=100.0 * abs(int(ha.sum()) - int(hb.sum())) / max(int(hb.sum()), 1),
                        disagree_rays=int((ha != hb).sum()), t_rel_gt_1e4=int((rel > 1e-4).sum()))
    med = lambda rs, k: statistics.median(x[k] for x in rs)
    print()
    print(f"triangles: {results[args.threads[0]][0][0]['triangles']} triangles, medians of {args.runs} interleaved runs")
    print(f"load: {open('/proc/loadavg').read().strip()}  ({time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())})")
    print("| threads | metric | Irradia | peer | Irradia / peer |")
    print("|---|---|---|---|---|")
    for n, (ir, em) in results.items():
        b_i, b_e = med(ir, "mesh_build_s"), med(em, "build_s")
        print(f"| {n} | peer: {em[0]['renderer']} | | | |")
        print(f"| {n} | build (s, lower is better) | {b_i:.3f} (BVH alone {med(ir, 'bvh_build_s'):.3f}) | {b_e:.3f} | {b_i / b_e:.2f} |")
        for k in ["primary", "incoherent"]:
            a, b = med(ir, f"{k}_mrays"), med(em, f"{k}_mrays")
            print(f"| {n} | {k} (Mrays/s) | {a:.2f} | {b:.2f} | {a / b:.2f} |")
    print()
    print("CPU seconds (user + system, all threads; on a loaded machine these show the work")
    print("done where wall time cannot; Embree's build CPU includes TBB workers spinning):")
    print("| threads | phase | Irradia CPU s | peer CPU s | Irradia / peer |")
    print("|---|---|---|---|---|")
    for n, (ir, em) in results.items():
        for k in ["build", "primary", "incoherent"]:
            a = statistics.median(x["cpu_s"][k] for x in ir)
            b = statistics.median(x["cpu_s"][k] for x in em)
            print(f"| {n} | {k} | {a:.3f} | {b:.3f} | {a / b:.2f} |")
    for s, v in agree.items():
        ok = "OK" if v["diff_pct"] <= 0.01 else "MISMATCH"
        print(f"hits {s}: irradia {v['irradia']} {last_peer} {v['embree']} ({v['diff_pct']:.4f}% apart, {ok}); "
              f"rays hit by one only: {v['disagree_rays']}; hit distances differing by >1e-4 relative: {v['t_rel_gt_1e4']}")


if __name__ == "__main__":
    main()
