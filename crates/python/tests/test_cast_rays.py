"""Scene.cast_rays against closed forms, in Open3D's RaycastingScene conventions."""

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
