#!/usr/bin/env python3
"""Why a scene cut into parts casts faster than the whole mesh: the gyroid of
bench/triangles as one mesh, as one mesh with its triangles in slab order, and cut into
K slabs (bench/python/cast_rays_gyroid.py's `--parts K`), each in Open3D and Irradia,
timed in one process, interleaved round by round on the same rays.

    python bench/python/cast_rays_split.py [--parts 8] [--rounds 5] [--sets incoherent]

Per round and set, in turn: Open3D on the whole mesh, on the whole mesh with its
triangles reordered by slab (the same triangles and vertices as the whole mesh, only
the order of `add_triangles`' index rows changed), on K geometries; then Irradia on
the whole mesh, on the slab-ordered mesh (a PLY written once beside the parts) and on
the K parts (`irradia.load_dict`, K `mesh` objects, traced through one flat mesh of all
their triangles, whose order is the slab order too). Prints each variant's median seconds
and the median per-round ratio to the whole mesh of the same library. If the
reordered mesh is as fast as the K geometries, the order of the triangles (the
builder's input order, and so the memory layout of leaves) explains the difference; if
only the K geometries differ, the treatment of several geometries does (for Irradia:
the flat mesh's traversal, whose rays outside a coherent group go one by one through
the 8-lane packet traversal to learn of near ties, where a sole mesh's go through the
single-ray traversal).
Needs the PLYs cast_rays_gyroid.py writes (run it once with `--parts K`).
"""

import argparse
import os
import statistics
import time

import numpy as np

import irradia

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--parts", type=int, default=8)
    ap.add_argument("--data", default=os.path.join(ROOT, "target", "bench-triangles"))
    ap.add_argument("--sets", nargs="+", default=["incoherent", "primary"])
    a = ap.parse_args()
    import open3d as o3d
    import sys

    sys.path.insert(0, HERE)
    from cast_rays_gyroid import split_parts, write_ply

    load = lambda name, dt: np.fromfile(os.path.join(a.data, name), dtype=dt).reshape(-1, 3)
    v, f = load("vertices.f32", "<f4"), load("indices.u32", "<u4")
    # The slab order: every triangle keeps its vertices (indices into the whole mesh's
    # vertex array), only the rows are sorted by slab.
    cx = v[f].mean(1)[:, 0]
    edges = np.quantile(cx, np.linspace(0, 1, a.parts + 1)[1:-1])
    which = np.searchsorted(edges, cx)
    f_sorted = np.ascontiguousarray(f[np.argsort(which, kind="stable")])
    parts = split_parts(v, f, a.parts)

    def o3d_scene(meshes):
        s = o3d.t.geometry.RaycastingScene(nthreads=a.threads)
        for vk, fk in meshes:
            s.add_triangles(o3d.core.Tensor(np.ascontiguousarray(vk)), o3d.core.Tensor(np.ascontiguousarray(fk, np.uint32)))
        s.cast_rays(o3d.core.Tensor(np.float32([[0, 0, 0, 0, 0, 1]])), nthreads=a.threads)
        return s

    o3d_scenes = {
        "o3d_whole": o3d_scene([(v, f)]),
        "o3d_sorted": o3d_scene([(v, f_sorted)]),
        f"o3d_{a.parts}_parts": o3d_scene(parts),
    }
    plys = [os.path.join(a.data, f"gyroid_{a.parts}_{k}.ply") for k in range(a.parts)]
    sorted_ply = os.path.join(a.data, f"gyroid_sorted_{a.parts}.ply")
    if not os.path.exists(sorted_ply):
        write_ply(sorted_ply, v, f_sorted)
    irr = {
        "irr_whole": irradia.load(os.path.join(a.data, "gyroid.ply")),
        "irr_sorted": irradia.load(sorted_ply),
        f"irr_{a.parts}_parts": irradia.load_dict({
            "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
            "materials": {"m": {"color": [0.5, 0.5, 0.5]}},
            "objects": [{"type": "mesh", "path": p, "material": "m"} for p in plys],
        }),
    }
    print(f"triangles={len(f)} parts={a.parts} threads={a.threads} open3d={o3d.__version__} "
          f"load {open('/proc/loadavg').read().split()[:3]}", flush=True)
    for s in a.sets:
        rays = np.ascontiguousarray(np.hstack([load(f"{s}_org.f32", "<f4"), load(f"{s}_dir.f32", "<f4")]), np.float32)
        rt = o3d.core.Tensor(rays)
        times = {k: [] for k in [*o3d_scenes, *irr]}
        for r in range(a.rounds + 1):
            for k, sc in o3d_scenes.items():
                t0 = time.perf_counter()
                sc.cast_rays(rt, nthreads=a.threads)
                if r:
                    times[k].append(time.perf_counter() - t0)
            for k, sc in irr.items():
                t0 = time.perf_counter()
                sc.cast_rays(rays, threads=a.threads)
                if r:
                    times[k].append(time.perf_counter() - t0)
        med = statistics.median
        rel = lambda k, base: med(x / y for x, y in zip(times[k], times[base]))
        print(f"RESULT set={s} " + " ".join(
            f"{k}_s={med(v_):.4f} {k}/whole={rel(k, 'o3d_whole' if k.startswith('o3d') else 'irr_whole'):.3f}"
            for k, v_ in times.items()), flush=True)
    print(f"loadavg: {open('/proc/loadavg').read().strip()} ({time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())})")


if __name__ == "__main__":
    main()
