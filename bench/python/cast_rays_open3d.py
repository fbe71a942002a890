#!/usr/bin/env python3
"""Scene.cast_rays against Open3D's RaycastingScene.cast_rays on the same triangle
mesh and the same rays, both on the same number of threads, interleaved.

    python bench/python/cast_rays_open3d.py [--rays 1000000] [--threads 2] [--subdiv 7]

The mesh: an icosphere (20 * 4^subdiv triangles) written as OBJ and read by both.
Prints the median times, the ratio irradia/open3d, and how many rays agree (hit or
miss alike, t within 1e-4 relative)."""

import argparse
import os
import statistics
import tempfile
import time

import numpy as np

import irradia


def icosphere(subdiv):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdiv):
        cache, nf = {}, []

        def mid(a, b):
            k = (min(a, b), max(a, b))
            if k not in cache:
                m = (v[a] + v[b]) / 2
                v.append(m / np.linalg.norm(m))
                cache[k] = len(v) - 1
            return cache[k]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return np.array(v, np.float32), np.array(f, np.int32)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rays", type=int, default=1_000_000)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--subdiv", type=int, default=7)
    ap.add_argument("--rounds", type=int, default=7)
    a = ap.parse_args()
    import open3d as o3d

    v, f = icosphere(a.subdiv)
    path = os.path.join(tempfile.mkdtemp(), "sphere.obj")
    with open(path, "w") as out:
        out.writelines("v %r %r %r\n" % tuple(map(float, p)) for p in v)
        out.writelines("f %d %d %d\n" % tuple(t + 1) for t in f)
    scene = irradia.load(path)
    rs = o3d.t.geometry.RaycastingScene(nthreads=a.threads)
    rs.add_triangles(o3d.core.Tensor(v), o3d.core.Tensor(f.astype(np.uint32)))
    rng = np.random.default_rng(1)
    o = rng.uniform(-1.5, 1.5, (a.rays, 3)).astype(np.float32)
    o[:, 2] = 3
    d = (rng.uniform(-0.3, 0.3, (a.rays, 3)) - [0, 0, 1]).astype(np.float32)
    rays = np.concatenate([o, d], 1)
    rt = o3d.core.Tensor(rays)
    ti, to = [], []
    for r in range(a.rounds + 1):
        t0 = time.perf_counter()
        hi = scene.cast_rays(rays, threads=a.threads)
        t1 = time.perf_counter()
        ho = rs.cast_rays(rt, nthreads=a.threads)
        t2 = time.perf_counter()
        if r:
            ti.append(t1 - t0)
            to.append(t2 - t1)
    a_t, b_t = hi["t_hit"], ho["t_hit"].numpy()
    both = np.isfinite(a_t) & np.isfinite(b_t)
    agree = (np.isfinite(a_t) == np.isfinite(b_t)) & (~both | (np.abs(a_t - b_t) <= 1e-4 * np.abs(b_t) + 1e-6))
    print(f"RESULT triangles={len(f)} rays={a.rays} threads={a.threads} irradia_s={statistics.median(ti):.4f} "
          f"open3d_s={statistics.median(to):.4f} ratio={statistics.median(x / y for x, y in zip(ti, to)):.3f} "
          f"hits={int(np.isfinite(a_t).sum())} agree={agree.mean():.6f} "
          f"open3d={o3d.__version__}")


if __name__ == "__main__":
    main()
