"""Sort-last compositing of a volume rendered with numpy, split over mpi4py ranks.

Each rank ray-casts its own slab of a density field (emission-absorption, orthographic
along -z) into a premultiplied RGBA float image, and Irradia's binary-swap compositor
combines the slabs with Porter-Duff "over" in visibility order (the slab nearest the
viewer in front) onto rank 0, which checks the result against the whole volume
rendered in one piece.

    mpirun -np 4 python examples/python/sort_last_volume.py [--size N] [--strategy S]
    python examples/python/sort_last_volume.py     # without MPI: the slabs in one process
"""

import argparse

import numpy as np

import irradia


def density(n):
    """Three Gaussian blobs in the unit cube, sampled on an n^3 grid (z, y, x)."""
    g = (np.arange(n, dtype=np.float32) + 0.5) / n
    z, y, x = np.meshgrid(g, g, g, indexing="ij")
    d = np.zeros((n, n, n), np.float32)
    for (cx, cy, cz), s, k in [((0.35, 0.4, 0.3), 0.12, 30), ((0.65, 0.6, 0.6), 0.15, 20), ((0.5, 0.3, 0.8), 0.08, 40)]:
        d += k * np.exp(-((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2) / (2 * s * s))
    return d


def transfer(d):
    """Colour by density (blue -> orange), premultiplied by the opacity of one step."""
    t = np.clip(d / 30, 0, 1)[..., None]
    rgb = (1 - t) * np.array([0.2, 0.4, 1.0], np.float32) + t * np.array([1.0, 0.6, 0.1], np.float32)
    return rgb.astype(np.float32)


def render_slab(vol, step):
    """Front-to-back emission-absorption along z (index 0 is nearest the viewer),
    premultiplied RGBA (h, w, 4)."""
    h, w = vol.shape[1:]
    acc = np.zeros((h, w, 4), np.float32)
    for k in range(vol.shape[0]):
        alpha = (1 - np.exp(-vol[k] * step)).astype(np.float32)[..., None]
        src = np.concatenate([transfer(vol[k]) * alpha, alpha], -1)
        acc += (1 - acc[..., 3:4]) * src
    return acc


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=96, help="grid points per axis")
    ap.add_argument("--strategy", default="binary-swap")
    ap.add_argument("--ranks", type=int, default=4, help="slabs when run without MPI")
    ap.add_argument("--out", default=None, help="write the composite here (.png/.exr/.pfm)")
    a = ap.parse_args()
    try:
        from mpi4py import MPI

        comm = MPI.COMM_WORLD
        rank, size = comm.Get_rank(), comm.Get_size()
    except ImportError:
        comm, rank, size = None, 0, a.ranks
    if comm is not None and not irradia.mpi_available():
        comm, size = None, a.ranks
    if comm is not None and size == 1:
        comm, size = None, a.ranks

    vol = density(a.size)
    step = 1.0 / a.size
    cuts = np.linspace(0, a.size, size + 1).astype(int)
    # Slab k is nearer the viewer than slab k+1: visibility order = rank order.
    order = list(range(size))
    if comm is not None:
        layer = render_slab(vol[cuts[rank]:cuts[rank + 1]], step)
        out = irradia.composite(layer, strategy=a.strategy, comm=comm, op="over", order=order)
    else:
        layers = np.stack([render_slab(vol[cuts[k]:cuts[k + 1]], step) for k in range(size)])
        out = irradia.composite(layers, op="over", order=order)
    if rank == 0:
        image = out[0]
        whole = render_slab(vol, step)
        err = np.abs(image - whole).max()
        print("%s %d slabs of a %d^3 volume: max difference to the one-piece render %.2e"
              % ("composited over MPI:" if comm is not None else "composited serially:", size, a.size, err))
        assert err < 1e-4, err
        if a.out:
            irradia.write_image(a.out, image[..., :3])


if __name__ == "__main__":
    main()
