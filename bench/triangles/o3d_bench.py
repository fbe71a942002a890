#!/usr/bin/env python3
"""Open3D 0.20's RaycastingScene (Embree inside, multi-threaded `cast_rays`) on the
triangles workload written by `triangles_bench write DIR`: the 2-thread anchor of
PEERS.md. Prints one JSON line of timings, in the form of embree_bench.py.

    python3 bench/triangles/o3d_bench.py DIR [THREADS]

- build: `add_triangles` plus the first `cast_rays` on one ray (Open3D commits, i.e.
  builds, the Embree scene on first use).
- primary / incoherent: one `cast_rays` call on all rays of the set, the rays
  already an Open3D tensor before the clock starts; THREADS is `nthreads` (default 2).
"""
import json, os, sys, time
import numpy as np

try:
    import open3d as o3d
except ImportError:
    print(json.dumps({"renderer": "open3d", "skipped": "open3d is not installed (pip install open3d-cpu)"}))
    sys.exit(0)

d = sys.argv[1]
threads = int(sys.argv[2]) if len(sys.argv) > 2 else 2
load = lambda name, dt: np.fromfile(os.path.join(d, name), dtype=dt).reshape(-1, 3)
vertices = load("vertices.f32", "<f4")
indices = load("indices.u32", "<u4")
rays = {}
for s in ["primary", "incoherent"]:
    r = np.hstack([load(f"{s}_org.f32", "<f4"), load(f"{s}_dir.f32", "<f4")]).astype(np.float32)
    rays[s] = o3d.core.Tensor(r)
one = o3d.core.Tensor(rays["primary"].numpy()[:1].copy())

c0 = time.process_time()
t0 = time.perf_counter()
scene = o3d.t.geometry.RaycastingScene(nthreads=threads)
scene.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(indices))
scene.cast_rays(one, nthreads=threads)
build_s = time.perf_counter() - t0
build_cpu = time.process_time() - c0

out, cpu = {}, {}
for s, r in rays.items():
    c0 = time.process_time()
    t0 = time.perf_counter()
    res = scene.cast_rays(r, nthreads=threads)
    sec = time.perf_counter() - t0
    cpu[s] = round(time.process_time() - c0, 3)
    t = res["t_hit"].numpy().astype(np.float32)
    t.tofile(os.path.join(d, f"{s}_t_open3d.f32"))
    n = r.shape[0]
    out[f"{s}_s"] = round(sec, 4)
    out[f"{s}_mrays"] = round(n / sec / 1e6, 3)
    out[f"{s}_hits"] = int(np.isfinite(t).sum())
print(json.dumps({"renderer": "open3d", "threads": threads, "triangles": len(indices),
                  "build_s": round(build_s, 4), **out,
                  "cpu_s": {"build": round(build_cpu, 3), **cpu}}))
