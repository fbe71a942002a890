"""composite() over mpi4py's COMM_WORLD, run by scripts/test-python.sh under
`mpirun -np 1..4 python -m pytest tests/test_composite_mpi.py`: every strategy equals
the serial composite (bit for bit for depth; within 1e-5 for float "over", as the
Rust MPI check). Skipped when mpi4py or this build's MPI is missing, unless
IRRADIA_REQUIRE_MPI=1."""

import os

import numpy as np
import pytest

import irradia
from layers import layer, stack

required = os.environ.get("IRRADIA_REQUIRE_MPI") == "1"
try:
    from mpi4py import MPI
except ImportError:  # pragma: no cover - depends on the machine
    MPI = None

if MPI is None or not irradia.mpi_available():
    if required:
        raise RuntimeError("mpi4py and an irradia built with --features mpi are required here")
    pytest.skip("mpi4py or irradia's MPI build missing", allow_module_level=True)

COMM = MPI.COMM_WORLD
RANK, SIZE = COMM.Get_rank(), COMM.Get_size()
STRATEGIES = ["direct-send", "tree", "binary-swap", "radix-k", "radix-3"]


@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize("dtype", [np.uint8, np.float32])
def test_depth_equals_serial(strategy, dtype):
    c, d = layer(RANK, dtype=dtype)
    out = irradia.composite(c, d, strategy=strategy, comm=COMM)
    sc, sd = stack(SIZE, dtype=dtype)
    ref_c, ref_d = irradia.composite(sc, sd)
    if RANK == 0:
        assert out is not None
        assert np.array_equal(out[0], ref_c) and np.array_equal(out[1], ref_d)
    else:
        assert out is None


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_over_in_order_equals_serial(strategy):
    order = list(reversed(range(SIZE)))
    c, _ = layer(RANK, opaque=False)
    root = SIZE - 1
    out = irradia.composite(c, strategy=strategy, comm=COMM, op="over", order=order, root=root)
    sc, _ = stack(SIZE, opaque=False)
    ref, _ = irradia.composite(sc, op="over", order=order)
    if RANK == root:
        assert np.abs(out[0] - ref).max() <= 1e-5
    else:
        assert out is None


@pytest.mark.parametrize("strategy", ["binary-swap", "radix-k"])
def test_display_tiles_equal_serial_crops(strategy):
    tiles = irradia.display_grid(53, 37, SIZE, 1, overlap=2)
    c, d = layer(RANK)
    out = irradia.composite(c, d, strategy=strategy, comm=COMM, tiles=tiles)
    sc, sd = stack(SIZE)
    ref_c, ref_d = irradia.composite(sc, sd)
    mine = [t for t in tiles if t[0] == RANK]
    if mine:
        _, x, y, w, h = mine[0]
        assert np.array_equal(out[0], ref_c[y:y + h, x:x + w]) and np.array_equal(out[1], ref_d[y:y + h, x:x + w])
    else:
        assert out is None


def sparse_layer(k, h=61, w=89, dtype=np.uint8):
    # A small blob per rank on background: the gather sends run lengths, not planes.
    c = np.zeros((h, w, 4), dtype)
    d = np.full((h, w), np.inf, np.float32)
    y, x = 3 + 7 * k % (h - 10), 5 + 11 * k % (w - 12)
    c[y:y + 6, x:x + 9] = 255 if dtype == np.uint8 else 1.0
    c[y:y + 6, x:x + 9, 0] = 40 * k % 256 if dtype == np.uint8 else k / 8
    d[y:y + 6, x:x + 9] = 1 + k % 3
    return c, d


@pytest.mark.parametrize("strategy", ["binary-swap", "direct-send", "radix-k"])
@pytest.mark.parametrize("rle", [True, False])
def test_sparse_and_dense_gathers_equal_serial(strategy, rle):
    # Sparse layers (gathered as runs, background pasted around them), then dense ones
    # (gathered as planes straight into the result), in turn and at several sizes: the
    # working layer kept between calls must not leak one call's pixels into the next.
    for h, w, make in ((61, 89, sparse_layer), (37, 53, layer), (61, 89, sparse_layer), (9, 4, layer)):
        mine = [make(k, h=h, w=w) if make is sparse_layer else make(k, h=h, w=w, dtype=np.uint8) for k in range(SIZE)]
        c, d = mine[RANK]
        keep_c, keep_d = c.copy(), d.copy()
        out = irradia.composite(c, d, strategy=strategy, comm=COMM, rle=rle)
        ref_c, ref_d = irradia.composite(np.stack([m[0] for m in mine]), np.stack([m[1] for m in mine]))
        assert np.array_equal(c, keep_c) and np.array_equal(d, keep_d)
        if RANK == 0:
            assert np.array_equal(out[0], ref_c) and np.array_equal(out[1], ref_d)
        else:
            assert out is None


def test_non_contiguous_layers_equal_serial():
    c, d = layer(RANK)
    fc, fd = np.asfortranarray(c), np.asfortranarray(d)
    out = irradia.composite(fc, fd, comm=COMM)
    sc, sd = stack(SIZE)
    ref_c, ref_d = irradia.composite(sc, sd)
    if RANK == 0:
        assert np.array_equal(out[0], ref_c) and np.array_equal(out[1], ref_d)
        assert out[0].flags.c_contiguous and isinstance(out[0].base, irradia._irradia.PooledBuffer)
    # The root's arrays come from a pool (src/pool.rs): a result the caller holds is
    # never written by the next composite, a freed one is reused.
    again = irradia.composite(c, d, comm=COMM)
    if RANK == 0:
        assert np.array_equal(out[0], ref_c) and np.array_equal(out[1], ref_d)
        assert np.array_equal(again[0], ref_c) and np.array_equal(again[1], ref_d)
        assert again[0].ctypes.data != out[0].ctypes.data


def test_caller_messages_untouched():
    # Irradia works on a duplicate of the communicator: a message of the caller's
    # posted before the composite is still there after it.
    dest, src = (RANK + 1) % SIZE, (RANK - 1) % SIZE
    req = COMM.isend(RANK, dest=dest, tag=7)
    c, d = layer(RANK)
    irradia.composite(c, d, comm=COMM)
    assert COMM.recv(source=src, tag=7) == src
    req.wait()


def test_one_duplicate_per_communicator():
    # The private duplicate Irradia composites over is made by the first composite over
    # a communicator and reused by the later ones (MPI_Comm_dup is collective: one per
    # frame cost round trips). A communicator the caller frees takes its duplicate
    # along; the next one (which may get the freed one's handle) gets its own: with
    # ranks in reverse order a stale duplicate would deliver to the wrong root and
    # break the depth ties (integer depths) the other way.
    c, d = layer(RANK)
    irradia.composite(c, d, comm=COMM)
    made = irradia._irradia._comm_duplicates()
    for _ in range(3):
        irradia.composite(c, d, comm=COMM)
    assert irradia._irradia._comm_duplicates() == made
    sc, sd = stack(SIZE)
    for k in range(4):
        backwards = k % 2 == 1
        sub = COMM.Split(0, key=SIZE - 1 - RANK if backwards else RANK)
        out = irradia.composite(c, d, strategy="binary-swap", comm=sub)
        out2 = irradia.composite(c, d, strategy="binary-swap", comm=sub)
        ref_c, ref_d = irradia.composite(sc[::-1].copy(), sd[::-1].copy()) if backwards else irradia.composite(sc, sd)
        if sub.Get_rank() == 0:
            for o in (out, out2):
                assert np.array_equal(o[0], ref_c) and np.array_equal(o[1], ref_d)
        else:
            assert out is None and out2 is None
        sub.Free()
        assert irradia._irradia._comm_duplicates() == made + k + 1
    # A duplicate of the communicator does not inherit the cached one.
    dup = COMM.Dup()
    out = irradia.composite(c, d, comm=dup)
    assert irradia._irradia._comm_duplicates() == made + 5
    dup.Free()
    ref_c, ref_d = irradia.composite(sc, sd)
    if RANK == 0:
        assert np.array_equal(out[0], ref_c) and np.array_equal(out[1], ref_d)


def test_errors_on_every_rank():
    c, d = layer(RANK)
    with pytest.raises(irradia.IrradiaError, match="root"):
        irradia.composite(c, d, comm=COMM, root=SIZE)
    with pytest.raises(irradia.IrradiaError, match="one layer"):
        irradia.composite(np.stack([c, c]), np.stack([d, d]), comm=COMM)
    with pytest.raises(irradia.IrradiaError, match="depth: expected a float32"):
        irradia.composite(c, d.astype(np.float64), comm=COMM)
    with pytest.raises(irradia.IrradiaError, match="uint8 or float32"):
        irradia.composite(c.astype(np.float16), d, comm=COMM)
