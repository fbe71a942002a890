#!/usr/bin/env python3
"""Embree 4 (through embreex) on the triangles workload written by
`triangles_bench write DIR`. Prints one JSON line of timings.

What is measured:
- build: `TriangleMesh(scene, vertices, indices)` plus the first query on one ray,
  which is when Embree commits (builds) the scene; the one-ray query is negligible.
- primary / incoherent: one `scene.run(origins, directions, output=1)` call on all
  rays of the set (embreex loops over them in C, one rtcIntersect1 per ray) -- the
  numpy arrays are prepared before the clock starts.
`embree_bench.py DIR memory` prints how far the peak resident size rose while building
the scene, above the loaded arrays (as `triangles_bench memory DIR`).
Embree's thread count is not exposed by embreex (rtcNewDevice gets no config), so the
caller pins the process to N cores with `taskset` to give it N threads.
"""
import json, os, sys, time
import numpy as np

try:
    from embreex import rtcore_scene as rtcs
    from embreex.mesh_construction import TriangleMesh
except ImportError:
    print(json.dumps({"renderer": "embree", "skipped": "embreex is not installed (pip install embreex)"}))
    sys.exit(0)

d = sys.argv[1]
load = lambda name, dt: np.fromfile(os.path.join(d, name), dtype=dt).reshape(-1, 3)
vertices = load("vertices.f32", "<f4")
indices = load("indices.u32", "<u4").astype(np.int32)
po, pd = load("primary_org.f32", "<f4"), load("primary_dir.f32", "<f4")
io, idr = load("incoherent_org.f32", "<f4"), load("incoherent_dir.f32", "<f4")
one_o, one_d = po[:1].copy(), pd[:1].copy()

if len(sys.argv) > 2 and sys.argv[2] == "memory":
    # Peak memory of the build above the loaded arrays, in one process (as
    # `triangles_bench memory`): reset the peak resident size (Linux: `5` to
    # /proc/self/clear_refs), note the resident size, build, report how far the peak rose.
    def status_kib(field):
        with open("/proc/self/status") as f:
            return next(int(l.split()[1]) for l in f if l.startswith(field))
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
    base = status_kib("VmRSS:")
    scene = rtcs.EmbreeScene()
    mesh = TriangleMesh(scene, vertices, indices)
    scene.run(one_o, one_d, output=1)
    peak = status_kib("VmHWM:")
    print(json.dumps({"renderer": "embree", "triangles": len(indices), "base_kib": base, "peak_kib": peak,
                      "build_kib": peak - base,
                      "bytes_per_triangle": round((peak - base) * 1024 / len(indices), 1)}))
    sys.exit(0)

c0 = time.process_time()
t0 = time.perf_counter()
scene = rtcs.EmbreeScene()
mesh = TriangleMesh(scene, vertices, indices)
scene.run(one_o, one_d, output=1)
build_s = time.perf_counter() - t0
build_cpu = time.process_time() - c0

cpu = []
def trace(o, dr):
    c0 = time.process_time()
    t0 = time.perf_counter()
    res = scene.run(o, dr, output=1)
    s = time.perf_counter() - t0
    cpu.append(time.process_time() - c0)
    t = np.where(res["geomID"] >= 0, res["tfar"], np.inf).astype(np.float32)
    return t, s

pt, p_s = trace(po, pd)
it, i_s = trace(io, idr)
pt.tofile(os.path.join(d, "primary_t_embree.f32"))
it.tofile(os.path.join(d, "incoherent_t_embree.f32"))
print(json.dumps({
    "renderer": "embree", "cores": len(os.sched_getaffinity(0)), "triangles": len(indices),
    "build_s": round(build_s, 4),
    "primary_s": round(p_s, 4), "primary_mrays": round(len(po) / p_s / 1e6, 3),
    "primary_hits": int(np.isfinite(pt).sum()),
    "incoherent_s": round(i_s, 4), "incoherent_mrays": round(len(io) / i_s / 1e6, 3),
    "incoherent_hits": int(np.isfinite(it).sum()),
    "cpu_s": {"build": round(build_cpu, 3), "primary": round(cpu[0], 3), "incoherent": round(cpu[1], 3)},
}))
