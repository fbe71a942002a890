"""Deterministic test layers for compositing: rank k's layer from seed k, the same
on every rank, so each rank can build the whole stack and the serial reference."""

import numpy as np


def layer(k, h=37, w=53, dtype=np.float32, opaque=True):
    rng = np.random.default_rng(1000 + k)
    cover = rng.uniform(size=(h, w)) < 0.6
    depth = np.where(cover, rng.integers(1, 20, size=(h, w)).astype(np.float32), np.float32(np.inf))
    if dtype == np.uint8:
        a = np.where(cover, 255 if opaque else rng.integers(0, 256, size=(h, w)), 0).astype(np.uint8)
        rgb = (rng.integers(0, 256, size=(h, w, 3)) * a[..., None] // 255).astype(np.uint8)
        color = np.concatenate([rgb, a[..., None]], -1)
    else:
        a = np.where(cover, 1.0 if opaque else rng.uniform(size=(h, w)), 0.0).astype(np.float32)
        color = np.concatenate([rng.uniform(size=(h, w, 3)).astype(np.float32) * a[..., None], a[..., None]], -1)
    return color.astype(dtype), depth.astype(np.float32)


def stack(n, **kw):
    ls = [layer(k, **kw) for k in range(n)]
    return np.stack([c for c, _ in ls]), np.stack([d for _, d in ls])
