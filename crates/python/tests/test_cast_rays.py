"""Scene.cast_rays against closed forms, in Open3D's RaycastingScene conventions."""

import json

import numpy as np
import pytest

import irradia

SCENE = {
    "image": {"width": 8, "height": 8},
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
    "materials": {"m": {"color": [0.5, 0.5, 0.5]}},
    "objects": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"},
        {"type": "sphere", "center": [3, 0, 0], "radius": 0.5, "material": "m"},
    ],
}


def grid_rays(n=41):
    xs = np.linspace(-1.2, 1.2, n, dtype=np.float32)
    x, y = np.meshgrid(xs, xs)
    o = np.stack([x, y, np.full_like(x, 5)], -1)
    d = np.zeros_like(o)
    d[..., 2] = -1
    return o, d


def test_sphere_closed_form():
    s = irradia.load_dict(SCENE)
    o, d = grid_rays()
    r = s.cast_rays(o, d)
    assert r["t_hit"].shape == o.shape[:2] and r["t_hit"].dtype == np.float32
    r2 = (o[..., 0] ** 2 + o[..., 1] ** 2).astype(np.float64)
    hit = r2 < 1
    expect = 5 - np.sqrt(np.clip(1 - r2, 0, None))
    inner = r2 < 0.98  # away from the grazing edge
    assert np.allclose(r["t_hit"][inner], expect[inner], atol=2e-5)
    assert np.isinf(r["t_hit"][~hit & (r2 > 1.02)]).all()
    assert (r["geometry_ids"][inner] == 0).all()
    miss = np.isinf(r["t_hit"])
    assert (r["geometry_ids"][miss] == irradia.INVALID_ID).all()
    assert (r["primitive_ids"][miss] == irradia.INVALID_ID).all()
    p = o + np.where(miss, 0, r["t_hit"])[..., None] * d
    assert np.allclose(r["primitive_normals"][inner], p[inner], atol=1e-4)
    assert r["primitive_uvs"].shape == o.shape[:2] + (2,)


def test_rays_of_shape_six_and_direction_length():
    s = irradia.load_dict(SCENE)
    rays = np.array([[[3, 0, 5, 0, 0, -1], [0, 0, 5, 0, 0, -2]]], dtype=np.float32)
    r = s.cast_rays(rays)
    assert r["t_hit"].shape == (1, 2)
    assert r["t_hit"][0, 0] == pytest.approx(4.5, abs=1e-5)
    assert r["geometry_ids"][0, 0] == 1
    # t is in units of the direction, as in Open3D.
    assert r["t_hit"][0, 1] == pytest.approx(2.0, abs=1e-5)
    r = s.cast_rays(rays, t_max=3.0)
    assert np.isinf(r["t_hit"][0, 0]) and r["t_hit"][0, 1] == pytest.approx(2.0, abs=1e-5)


def test_threads_and_mesh_primitives(data):
    s = irradia.load(data / "ply" / "quad_le.ply")
    rng = np.random.default_rng(1)
    o = rng.uniform(-2, 2, (5000, 3)).astype(np.float32)
    d = rng.normal(size=(5000, 3)).astype(np.float32)
    a = s.cast_rays(o, d, threads=1)
    b = s.cast_rays(o, d, threads=2)
    for k in a:
        assert np.array_equal(a[k], b[k])
    hit = np.isfinite(a["t_hit"])
    assert hit.any()
    assert set(np.unique(a["primitive_ids"][hit])) <= {0, 1}


def test_bad_rays():
    s = irradia.load_dict(SCENE)
    with pytest.raises(irradia.IrradiaError, match=r"\(\.\.\., 6\)"):
        s.cast_rays(np.zeros((4, 5), np.float32))
    with pytest.raises(irradia.IrradiaError, match="same shape"):
        s.cast_rays(np.zeros((4, 3), np.float32), np.zeros((5, 3), np.float32))
    bad = np.zeros((2, 6), np.float32)
    bad[1, 0] = np.nan
    with pytest.raises(irradia.IrradiaError, match=r"rays\[1\]"):
        s.cast_rays(bad)
    with pytest.raises(TypeError):
        s.cast_rays(np.zeros((2, 6), np.float64))
    with pytest.raises(irradia.IrradiaError, match="t_max"):
        s.cast_rays(np.zeros((2, 6), np.float32), t_max=-1.0)


def _icosphere_triangles(subdiv=1):
    """An icosphere's triangles as (n, 3, 3) corners, wound outwards."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    tris = np.array([[v[i] for i in tri] for tri in f], np.float64)
    tris /= np.linalg.norm(tris, axis=-1, keepdims=True)
    for _ in range(subdiv):
        a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
        ab, bc, ca = [m / np.linalg.norm(m, axis=-1, keepdims=True) for m in ((a + b) / 2, (b + c) / 2, (c + a) / 2)]
        tris = np.concatenate([np.stack(x, 1) for x in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))])
    return tris.astype(np.float32)


def _mesh_scene():
    """Two `triangles` objects with unshared corners (so that the renderer's shading
    normal is the face's own): an icosphere and a quad behind it."""
    sphere = _icosphere_triangles()
    quad = np.array([[[-1.5, -1.5, -2], [1.5, -1.5, -2], [1.5, 1.5, -2]], [[-1.5, -1.5, -2], [1.5, 1.5, -2], [-1.5, 1.5, -2]]],
                    np.float32)
    objects = [
        {"type": "triangles", "positions": tris.reshape(-1, 3).tolist(),
         "indices": np.arange(3 * len(tris)).reshape(-1, 3).tolist(), "material": "m"}
        for tris in (sphere, quad)
    ]
    doc = {
        "image": {"width": 24, "height": 18},
        "camera": {"eye": [0.3, 0.2, 4], "look_at": [0, 0, 0], "fov": 50},
        "materials": {"m": {"color": [0.5, 0.5, 0.5]}},
        "lights": [{"type": "point", "position": [2, 3, 5], "intensity": 20}],
        "objects": objects,
    }
    return doc, [sphere, quad]


def _reference(objects, o, d):
    """Closest hits by brute force in float64 (Moeller-Trumbore over every triangle):
    t, object, triangle, barycentric (b1, b2), unit geometric normal, and the smallest
    barycentric (how far inside its triangle the hit is)."""
    o, d = o.astype(np.float64), d.astype(np.float64)
    n = len(o)
    best = dict(t=np.full(n, np.inf), obj=np.full(n, -1), prim=np.full(n, -1), uv=np.zeros((n, 2)),
                normal=np.zeros((n, 3)), margin=np.zeros(n))
    for oi, tris in enumerate(objects):
        tris = tris.astype(np.float64)
        p0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
        pv = np.cross(d[:, None], e2[None])
        det = np.einsum("rtk,tk->rt", pv, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1 / det
            s = o[:, None] - p0[None]
            u = np.einsum("rtk,rtk->rt", s, pv) * inv
            q = np.cross(s, e1[None])
            v = np.einsum("rk,rtk->rt", d, q) * inv
            t = np.einsum("tk,rtk->rt", e2, q) * inv
        ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        t = np.where(ok, t, np.inf)
        k = np.argmin(t, 1)
        tk = t[np.arange(n), k]
        closer = tk < best["t"]
        r = np.arange(n)[closer]
        kk = k[closer]
        uu, vv = u[r, kk], v[r, kk]
        ng = np.cross(e1[kk], e2[kk])
        best["t"][closer] = tk[closer]
        best["obj"][closer] = oi
        best["prim"][closer] = kk
        best["uv"][closer] = np.stack([uu, vv], -1)
        best["normal"][closer] = ng / np.linalg.norm(ng, axis=-1, keepdims=True)
        best["margin"][closer] = np.minimum(np.minimum(uu, vv), 1 - uu - vv)
    return best


def test_mesh_against_reference_and_cli(cli, tmp_path):
    """cast_rays on a small mesh scene against the renderer's own ray query (the camera
    rays of `irradia trace-pixel --format json`: object, point, normal) and against a
    float64 brute-force intersection (t, object and triangle ids, uv, normal)."""
    doc, objects = _mesh_scene()
    path = tmp_path / "mesh.json"
    path.write_text(json.dumps(doc))
    s = irradia.load(path)

    # The CLI's camera rays: the renderer's closest hit of each.
    pixels = [(x, y) for x in (1, 5, 9, 12, 15, 19, 23) for y in (2, 8, 13, 17)]
    rays, want = [], []
    for x, y in pixels:
        node = json.loads(cli("trace-pixel", path, x, y, "--format", "json").stdout)["tree"]
        assert node["kind"] == "camera"
        rays.append(node["origin"] + node["direction"])
        want.append(node)
    r = s.cast_rays(np.array(rays, np.float32))
    n_hit = 0
    for k, node in enumerate(want):
        hit = node.get("hit")
        if not hit:
            assert np.isinf(r["t_hit"][k]) and r["geometry_ids"][k] == irradia.INVALID_ID, (pixels[k], node)
            continue
        n_hit += 1
        assert r["geometry_ids"][k] == hit["object"], (pixels[k], hit)
        p = np.array(rays[k][:3]) + r["t_hit"][k] * np.array(rays[k][3:])
        assert np.allclose(p, hit["point"], rtol=1e-5, atol=1e-5), (pixels[k], p, hit)
        assert abs(np.dot(r["primitive_normals"][k], hit["normal"])) > 0.9999, (pixels[k], hit)
    assert 0 < n_hit < len(want)

    # Many rays, some past the sphere to the quad, some missing both.
    rng = np.random.default_rng(7)
    o = np.column_stack([rng.uniform(-0.5, 0.5, 3000), rng.uniform(-0.5, 0.5, 3000), np.full(3000, 4.0)])
    aim = rng.uniform(-3.5, 3.5, (3000, 3)) * [1, 1, 0] + [0, 0, -2]
    d = ((aim - o) * rng.uniform(0.5, 2, (3000, 1))).astype(np.float32)
    o = o.astype(np.float32)
    r = s.cast_rays(o, d)
    ref = _reference(objects, o, d)
    hit = np.isfinite(ref["t"])
    inside = hit & (ref["margin"] > 1e-4)  # away from edges, where float32 may pick the neighbour
    assert hit.sum() > 400 and (~hit).sum() > 1000 and (ref["obj"] == 1).sum() > 100
    assert np.array_equal(np.isfinite(r["t_hit"])[inside | ~hit], hit[inside | ~hit])
    assert np.allclose(r["t_hit"][inside], ref["t"][inside], rtol=1e-4, atol=0)
    assert np.array_equal(r["geometry_ids"][inside], ref["obj"][inside])
    assert np.array_equal(r["primitive_ids"][inside], ref["prim"][inside])
    assert np.allclose(r["primitive_uvs"][inside], ref["uv"][inside], atol=1e-4)
    assert (np.sum(r["primitive_normals"][inside] * ref["normal"][inside], -1) > 0.9999).all()
    miss = ~hit & ~np.isfinite(r["t_hit"])
    assert (r["primitive_ids"][miss] == irradia.INVALID_ID).all()
    assert (r["primitive_uvs"][miss] == 0).all() and (r["primitive_normals"][miss] == 0).all()
    # The same answers from the (..., 6) form, on one thread and on two.
    packed = np.concatenate([o, d], -1)
    for threads in (1, 2):
        r6 = s.cast_rays(packed, threads=threads)
        for key in r:
            assert np.array_equal(r6[key], r[key]), key


def test_sole_mesh_fast_path_equals_general_path():
    """A scene of one untransformed mesh is traced straight against that mesh's own
    hierarchy; the same mesh beside a second object (which no ray here reaches) goes
    through the scene's two-level hierarchy. Every answer must be the same, bit for
    bit, for coherent and incoherent rays, with and without t_max, on 1 and 2 threads.
    The sole mesh traces groups of eight coherent rays as packets (the primary rays
    here), the general path every ray alone, so this also holds packets to single rays."""
    mesh = {"type": "gyroid_mesh", "grid": 40, "material": "m"}
    far = {"type": "sphere", "center": [50, 50, 50], "radius": 1, "material": "m"}
    base = {k: v for k, v in SCENE.items() if k != "objects"}
    alone = irradia.load_dict({**base, "objects": [mesh]})
    beside = irradia.load_dict({**base, "objects": [mesh, far]})
    rng = np.random.default_rng(11)
    n = 20000
    incoherent = np.concatenate([rng.uniform(-1.2, 1.2, (n, 3)), rng.normal(size=(n, 3))], -1)
    xs = np.linspace(-0.6, 0.6, 141)
    x, y = np.meshgrid(xs, xs)
    d = np.stack([x, y, -np.ones_like(x)], -1).reshape(-1, 3)
    primary = np.concatenate([np.broadcast_to([0.1, 0.2, 2.5], d.shape), d], -1)
    for rays in (incoherent.astype(np.float32), primary.astype(np.float32)):
        for t_max, threads in ((None, 1), (None, 2), (2.0, 2)):
            a = alone.cast_rays(rays, t_max=t_max, threads=threads)
            b = beside.cast_rays(rays, t_max=t_max, threads=threads)
            hit = np.isfinite(b["t_hit"])
            assert hit.sum() > len(rays) // 4
            assert (b["geometry_ids"][hit] == 0).all()
            for key in a:
                assert np.array_equal(a[key], b[key]), (key, t_max, threads)
        # The kernel timing runs both ways (packets and ray by ray, for paired timings).
        assert alone._cast_rays_kernel_seconds(rays, threads=1, packets=False) > 0
        assert alone._cast_rays_kernel_seconds(rays, threads=1) > 0


def test_several_objects_batched_equals_single_rays():
    """A scene of several objects (gyroid meshes side by side, one turned and scaled,
    one a copy in the same place as another, so that their hits tie, and a sphere):
    coherent groups of eight rays go through the top level and each mesh together as
    packets. Every answer must equal the single-ray query's (`_cast_rays_single`), bit
    for bit, for coherent and incoherent rays, with and without t_max, on 1 and 2
    threads."""
    mesh = {"type": "gyroid_mesh", "grid": 24, "material": "m"}
    objects = [
        {**mesh, "transform": [{"scale": 0.5}, {"translate": [-0.6, 0, 0]}]},
        {**mesh, "transform": [{"scale": 0.5}, {"translate": [0.6, 0, 0]}]},
        {**mesh, "transform": [{"scale": 0.5}, {"translate": [0.6, 0, 0]}]},
        {**mesh, "transform": [{"scale": [0.4, 0.3, 0.5]}, {"rotate": [20, 35, 0]}, {"translate": [0, 0.7, 0.3]}]},
        {"type": "sphere", "center": [0, -0.7, 0.4], "radius": 0.3, "material": "m"},
    ]
    base = {k: v for k, v in SCENE.items() if k != "objects"}
    two_levels = irradia.load_dict({**base, "objects": objects})
    # Untransformed meshes only: traced through one flat mesh of all their triangles
    # (the same mesh twice: every hit there ties, and is traced again alone).
    flat = irradia.load_dict({**base, "objects": [mesh, {**mesh, "grid": 17}, mesh]})
    rng = np.random.default_rng(5)
    n = 20000
    incoherent = np.concatenate([rng.uniform(-1.2, 1.2, (n, 3)), rng.normal(size=(n, 3))], -1)
    xs = np.linspace(-0.6, 0.6, 141)
    x, y = np.meshgrid(xs, xs)
    d = np.stack([x, y, -np.ones_like(x)], -1).reshape(-1, 3)
    primary = np.concatenate([np.broadcast_to([0.1, 0.2, 2.5], d.shape), d], -1)
    for scene, hit_objects in ((two_levels, {0, 1, 3, 4}), (flat, {0, 1})):
        for rays in (incoherent.astype(np.float32), primary.astype(np.float32)):
            for t_max, threads in ((None, 1), (None, 2), (2.6, 2)):
                a = scene.cast_rays(rays, t_max=t_max, threads=threads)
                b = scene._cast_rays_single(rays, t_max=t_max, threads=threads)
                hit = np.isfinite(b["t_hit"])
                assert hit.sum() > len(rays) // 5
                # Every object but the copy is hit (the copy ties with the first
                # everywhere and the single-ray order settles every tie the same way).
                assert hit_objects <= set(np.unique(b["geometry_ids"][hit]).tolist())
                for key in a:
                    assert np.array_equal(a[key], b[key]), (key, t_max, threads)
            assert scene._cast_rays_kernel_seconds(rays, threads=1, packets=False) > 0
            assert scene._cast_rays_kernel_seconds(rays, threads=1) > 0
