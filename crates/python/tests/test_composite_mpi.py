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


def test_caller_messages_untouched():
    # Irradia works on a duplicate of the communicator: a message of the caller's
    # posted before the composite is still there after it.
    dest, src = (RANK + 1) % SIZE, (RANK - 1) % SIZE
    req = COMM.isend(RANK, dest=dest, tag=7)
    c, d = layer(RANK)
    irradia.composite(c, d, comm=COMM)
    assert COMM.recv(source=src, tag=7) == src
    req.wait()


def test_errors_on_every_rank():
    c, d = layer(RANK)
    with pytest.raises(irradia.IrradiaError, match="root"):
        irradia.composite(c, d, comm=COMM, root=SIZE)
    with pytest.raises(irradia.IrradiaError, match="one layer"):
        irradia.composite(np.stack([c, c]), np.stack([d, d]), comm=COMM)
