#!/usr/bin/env python3
"""Scene.cast_rays against Open3D's RaycastingScene.cast_rays on the triangles workload
(bench/triangles: the 2.25M-triangle gyroid, 1280x720 primary rays and 1e6 incoherent
rays), the same rays, both on the same number of threads, interleaved.

    python bench/python/cast_rays_gyroid.py [--threads 2] [--rounds 7] [--data DIR] [--parts K]

DIR (default target/bench-triangles) holds the raw arrays of `triangles_bench write
DIR` (built and run here when missing); the mesh is also written there once as a
binary little-endian PLY, which `irradia.load` reads (Open3D gets the same arrays).

`--parts K` (K > 1) cuts the mesh into K slabs along x (each triangle to the slab of
its centroid; every part keeps only the vertices it uses) and gives both sides a scene
of K meshes: Irradia loads the parts' PLYs as K `mesh` objects (a two-level hierarchy,
rays traced through the top level and then each part's), Open3D gets K
`add_triangles`; geometry ids are compared too. Then the kernel column is the same
scene's rays traced one by one through the hierarchy (`packets=False`, the path before
top-level packets), and `single/batched` its ratio to the batched `cast_rays` of the same
round (which includes the binding, so the ratio understates the kernel's gain).

Per round and ray set, in turn: `scene.cast_rays(rays, threads=N)` (numpy (n, 6) in,
the five result arrays out), Open3D's `cast_rays(tensor, nthreads=N)` (the rays made
an Open3D tensor before the clock, as bench/triangles/o3d_bench.py does), and the
binding's kernel alone (`scene._cast_rays_kernel_seconds`: the same batched queries on
the same threads, no numpy in or out). Prints the medians, the median of the per-round
ratios irradia / open3d, what the binding adds (cast_rays minus the kernel), and the
agreement: hit or miss alike, t within 1e-4 relative, the same triangle id, normals
parallel and uvs within 1e-3 where both hit. Nothing is pinned: run it under
`taskset -c 0,1` to pin, and note the load (printed) beside any figure.
"""

import argparse
import os
import statistics
import subprocess
import sys
import time

import numpy as np

import irradia

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def ensure_data(d):
    if os.path.exists(os.path.join(d, "incoherent_dir.f32")):
        return
    subprocess.run(["cargo", "build", "--release", "-p", "irradia-geometry", "--example", "triangles_bench"],
                   cwd=ROOT, check=True)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    subprocess.run([os.path.join(target, "release", "examples", "triangles_bench"), "write", d], check=True)


def write_ply(path, v, f):
    """Binary little-endian PLY: float x y z, faces as uchar count + int indices."""
    faces = np.empty(len(f), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = f
    tmp = path + ".tmp"
    with open(tmp, "wb") as out:
        out.write(("ply\nformat binary_little_endian 1.0\n"
                   f"element vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
                   f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        out.write(np.ascontiguousarray(v, "<f4").tobytes())
        out.write(faces.tobytes())
    os.replace(tmp, path)


def split_parts(v, f, parts):
    """The mesh cut into `parts` slabs along x by triangle centroid, each with only the
    vertices it uses (indices renumbered)."""
    cx = v[f].mean(1)[:, 0]
    edges = np.quantile(cx, np.linspace(0, 1, parts + 1)[1:-1])
    which = np.searchsorted(edges, cx)
    out = []
    for k in range(parts):
        fk = f[which == k]
        used, inv = np.unique(fk.reshape(-1), return_inverse=True)
        out.append((np.ascontiguousarray(v[used]), inv.reshape(-1, 3).astype(np.uint32)))
    return out


def agreement(hi, ho):
    a_t, b_t = hi["t_hit"], ho["t_hit"].numpy()
    ha, hb = np.isfinite(a_t), np.isfinite(b_t)
    both = ha & hb
    rel = np.abs(a_t[both] - b_t[both]) / np.maximum(np.abs(b_t[both]), 1e-30)
    same_id = hi["primitive_ids"][both] == ho["primitive_ids"].numpy()[both]
    dots = np.abs(np.sum(hi["primitive_normals"][both] * ho["primitive_normals"].numpy()[both], -1))
    duv = np.abs(hi["primitive_uvs"][both] - ho["primitive_uvs"].numpy()[both]).max(-1, initial=0)
    same_geometry = hi["geometry_ids"][both] == ho["geometry_ids"].numpy()[both]
    miss_ok = np.all(hi["primitive_ids"][~ha] == irradia.INVALID_ID) and np.all(hi["geometry_ids"][~ha] == irradia.INVALID_ID)
    return dict(hits=int(ha.sum()), open3d_hits=int(hb.sum()), hit_by_one_only=int((ha != hb).sum()),
                t_rel_gt_1e4=int((rel > 1e-4).sum()), geometry_differs=int((~same_geometry).sum()), id_differs=int((~same_id).sum()),
                normal_not_parallel=int((dots < 0.999).sum()), uv_gt_1e3=int((duv > 1e-3).sum()),
                misses_invalid=bool(miss_ok))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--data", default=os.path.join(ROOT, "target", "bench-triangles"))
    ap.add_argument("--sets", nargs="+", default=["primary", "incoherent"])
    ap.add_argument("--parts", type=int, default=1, help="cut the mesh into this many meshes (slabs along x)")
    a = ap.parse_args()
    import open3d as o3d

    ensure_data(a.data)
    load = lambda name, dt: np.fromfile(os.path.join(a.data, name), dtype=dt).reshape(-1, 3)
    v, f = load("vertices.f32", "<f4"), load("indices.u32", "<u4")
    parts = [(v, f)] if a.parts <= 1 else split_parts(v, f, a.parts)
    plys = []
    for k, (vk, fk) in enumerate(parts):
        ply = os.path.join(a.data, "gyroid.ply" if a.parts <= 1 else f"gyroid_{a.parts}_{k}.ply")
        if not os.path.exists(ply):
            write_ply(ply, vk, fk)
        plys.append(ply)
    t0 = time.perf_counter()
    if a.parts <= 1:
        scene = irradia.load(plys[0])
    else:
        scene = irradia.load_dict({
            "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
            "materials": {"m": {"color": [0.5, 0.5, 0.5]}},
            "objects": [{"type": "mesh", "path": p, "material": "m"} for p in plys],
        })
    load_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    rs = o3d.t.geometry.RaycastingScene(nthreads=a.threads)
    for vk, fk in parts:
        rs.add_triangles(o3d.core.Tensor(vk), o3d.core.Tensor(fk))
    rs.cast_rays(o3d.core.Tensor(np.float32([[0, 0, 0, 0, 0, 1]])), nthreads=a.threads)
    o3d_build_s = time.perf_counter() - t0
    print(f"triangles={len(f)} parts={len(parts)} irradia load+build {load_s:.2f}s open3d build {o3d_build_s:.2f}s "
          f"open3d={o3d.__version__} threads={a.threads}", flush=True)
    for s in a.sets:
        rays = np.ascontiguousarray(np.hstack([load(f"{s}_org.f32", "<f4"), load(f"{s}_dir.f32", "<f4")]), np.float32)
        rt = o3d.core.Tensor(rays)
        ti, to, tk = [], [], []
        loads = []
        for r in range(a.rounds + 1):
            t0 = time.perf_counter()
            hi = scene.cast_rays(rays, threads=a.threads)
            t1 = time.perf_counter()
            ho = rs.cast_rays(rt, nthreads=a.threads)
            t2 = time.perf_counter()
            k = scene._cast_rays_kernel_seconds(rays, threads=a.threads, packets=a.parts <= 1)
            if r:  # round 0 warms up
                ti.append(t1 - t0)
                to.append(t2 - t1)
                tk.append(k)
                loads.append(os.getloadavg()[0])
        med = statistics.median
        ratios = [x / y for x, y in zip(ti, to)]
        ag = agreement(hi, ho)
        print(f"RESULT set={s} rays={len(rays)} threads={a.threads} irradia_s={med(ti):.4f} open3d_s={med(to):.4f} "
              f"ratio={med(ratios):.3f} (pairs {min(ratios):.3f}-{max(ratios):.3f}) kernel_s={med(tk):.4f} "
              f"kernel_ratio={med(x / y for x, y in zip(tk, to)):.3f} "
              + (f"single/batched={med(k / i for k, i in zip(tk, ti)):.3f} " if a.parts > 1 else "")
              + f"binding_s={med(x - y for x, y in zip(ti, tk)):.4f} "
              f"load1={min(loads):.1f}-{max(loads):.1f}", flush=True)
        print(f"AGREE set={s} " + " ".join(f"{k}={v}" for k, v in ag.items()), flush=True)
    print(f"loadavg: {open('/proc/loadavg').read().strip()} ({time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())})")


if __name__ == "__main__":
    main()
