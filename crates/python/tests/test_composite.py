"""composite() without a communicator (one process's layers, serially) against numpy,
and its errors; tests/test_composite_mpi.py runs the same under mpirun."""

import numpy as np
import pytest

import irradia
from layers import stack


def numpy_depth(colors, depths, order):
    out_c, out_d = colors[order[0]].copy(), depths[order[0]].copy()
    for k in order[1:]:
        nearer = depths[k] < out_d  # ties: the one earlier in the order stays
        out_c[nearer] = colors[k][nearer]
        out_d[nearer] = depths[k][nearer]
    return out_c, out_d


@pytest.mark.parametrize("dtype", [np.uint8, np.float32])
def test_serial_depth_composite(dtype):
    c, d = stack(5, dtype=dtype)
    for order in (None, [3, 1, 4, 0, 2]):
        got_c, got_d = irradia.composite(c, d, order=order)
        ref_c, ref_d = numpy_depth(c, d, order or list(range(5)))
        assert got_c.dtype == dtype
        assert np.array_equal(got_c, ref_c) and np.array_equal(got_d, ref_d)


def test_serial_over_float():
    c, _ = stack(4, opaque=False)
    order = [2, 0, 3, 1]
    got, _ = irradia.composite(c, op="over", order=order)
    acc = c[order[0]].astype(np.float32)
    for k in order[1:]:
        acc = acc + (1 - acc[..., 3:4]) * c[k]
    assert np.allclose(got, acc, atol=1e-6)


def test_serial_over_uint8_exact_rounding():
    c, _ = stack(3, dtype=np.uint8, opaque=False)
    got, _ = irradia.composite(c)  # no depth: "over" in rank order
    acc = c[0].astype(np.uint32)
    for k in (1, 2):
        t = c[k].astype(np.uint32) * (255 - acc[..., 3:4]) + 128
        acc = np.minimum(acc + ((t + (t >> 8)) >> 8), 255)
    assert np.array_equal(got, acc.astype(np.uint8))


def test_single_layer_is_itself():
    c, d = stack(1)
    got_c, got_d = irradia.composite(c[0], d[0])
    assert np.array_equal(got_c, c[0]) and np.array_equal(got_d, d[0])


def test_composite_errors():
    c, d = stack(3)
    with pytest.raises(irradia.IrradiaError, match="RGBA"):
        irradia.composite(c[..., :3], d)
    with pytest.raises(irradia.IrradiaError, match="depth: expected shape"):
        irradia.composite(c, d[:2])
    with pytest.raises(irradia.IrradiaError, match="order"):
        irradia.composite(c, d, order=[0, 0, 1])
    with pytest.raises(irradia.IrradiaError, match="unknown operator"):
        irradia.composite(c, d, op="add")
    with pytest.raises(irradia.IrradiaError, match="uint8 or float32"):
        irradia.composite(c.astype(np.float64), d)
    bad = d.copy()
    bad[0, 0, 0] = np.nan
    with pytest.raises(irradia.IrradiaError, match="NaN"):
        irradia.composite(c, bad)
    with pytest.raises(irradia.IrradiaError, match="py2f|without MPI"):
        irradia.composite(c[0], d[0], comm=object())


def test_arrays_are_read_in_place_and_left_alone():
    # C-contiguous arrays are read where they lie; other layouts (Fortran order, strided
    # and reversed views) are copied once and give the same composite.
    c, d = stack(3)
    ref_c, ref_d = irradia.composite(c, d)
    keep_c, keep_d = c.copy(), d.copy()
    views = [
        (np.asfortranarray(c), np.asfortranarray(d), lambda a: a),
        (np.stack([c, c], 3)[..., 0, :], np.stack([d, d], 3)[..., 0], lambda a: a),
        (c[:, ::-1], d[:, ::-1], lambda a: a[::-1]),
    ]
    for vc, vd, flip in views:
        assert not vc.flags.c_contiguous and not vd.flags.c_contiguous
        got_c, got_d = irradia.composite(vc, vd)
        assert np.array_equal(got_c, flip(ref_c)) and np.array_equal(got_d, flip(ref_d))
    ro_c, ro_d = c.copy(), d.copy()
    ro_c.flags.writeable = ro_d.flags.writeable = False
    got_c, got_d = irradia.composite(ro_c, ro_d)
    assert np.array_equal(got_c, ref_c) and np.array_equal(got_d, ref_d)
    assert np.array_equal(c, keep_c) and np.array_equal(d, keep_d)
    # The result is the caller's own: fresh, writable, C-contiguous, on memory owned by
    # its base object (the pool's buffer, crates/python/src/pool.rs).
    from irradia import _irradia

    for a in (got_c, got_d):
        assert a.flags.c_contiguous and a.flags.writeable
        assert isinstance(a.base, _irradia.PooledBuffer)
    got_c[...] = 0
    assert np.array_equal(irradia.composite(c, d)[0], ref_c)


def test_wrong_dtypes_raise():
    c, d = stack(2)
    with pytest.raises(irradia.IrradiaError, match="depth: expected a float32"):
        irradia.composite(c, d.astype(np.float64))
    with pytest.raises(irradia.IrradiaError, match="depth: expected a float32"):
        irradia.composite(c, d.tolist())
    with pytest.raises(irradia.IrradiaError, match="uint8 or float32"):
        irradia.composite(c.astype(np.int32), d)
    with pytest.raises(irradia.IrradiaError, match="uint8 or float32"):
        irradia.composite(c.tolist(), d)


def test_over_without_depth_and_sizes_in_turn():
    # No depth: background depth everywhere; different sizes one after another.
    for h, w in ((37, 53), (5, 7), (64, 48), (37, 53)):
        c, _ = stack(2, h=h, w=w, opaque=False)
        got_c, got_d = irradia.composite(c, op="over")
        ref, _ = irradia.composite(c, np.full(c.shape[:3], np.inf, np.float32), op="over")
        assert got_c.shape == (h, w, 4) and np.array_equal(got_c, ref)
        assert np.all(np.isinf(got_d))


def test_serial_tiles_are_crops():
    c, d = stack(3)
    tiles = irradia.display_grid(53, 37, 2, 2, overlap=3)
    assert len(tiles) == 4 and tiles[0][0] == 0
    full_c, full_d = irradia.composite(c, d)
    parts = irradia.composite(c, d, tiles=tiles)
    for (rank, x, y, w, h), (tc, td) in zip(tiles, parts):
        assert np.array_equal(tc, full_c[y:y + h, x:x + w]) and np.array_equal(td, full_d[y:y + h, x:x + w])
    with pytest.raises(irradia.IrradiaError, match="tiles"):
        irradia.composite(c, d, tiles=[(0, 50, 0, 10, 10)])
    with pytest.raises(irradia.IrradiaError):
        irradia.display_grid(10, 10, 0, 1)


def test_result_memory_is_reused_only_after_the_caller_frees_it():
    # The returned arrays come from a pool (crates/python/src/pool.rs) so that a loop of
    # composites does not page-fault its results in again. An array the caller still
    # holds must never be written by a later call; a freed one is taken again.
    from irradia import _irradia

    c, d = stack(3, dtype=np.uint8)
    first_c, first_d = irradia.composite(c, d)
    kept_c, kept_d = first_c.copy(), first_d.copy()
    c2, d2 = c[::-1].copy(), d[::-1].copy()  # a different image into the next result
    second_c, second_d = irradia.composite(c2, d2)
    assert not np.array_equal(second_c, kept_c)
    assert np.array_equal(first_c, kept_c) and np.array_equal(first_d, kept_d)
    addr = lambda a: a.__array_interface__["data"][0]
    held = {addr(first_c), addr(first_d)}
    assert addr(second_c) not in held and addr(second_d) not in held
    assert isinstance(first_c.base, _irradia.PooledBuffer)

    old = {addr(second_c), addr(second_d)}
    del second_c, second_d
    allocated, reused = _irradia._pool_stats()
    third_c, third_d = irradia.composite(c2, d2)
    assert {addr(third_c), addr(third_d)} == old
    assert _irradia._pool_stats() == (allocated, reused + 2)
    ref_c, ref_d = numpy_depth(c2, d2, [0, 1, 2])
    assert np.array_equal(third_c, ref_c) and np.array_equal(third_d, ref_d)
    # A view outliving its array keeps the memory too.
    view = third_c[1:, 1:]
    snapshot = view.copy()
    del third_c, third_d
    for _ in range(3):
        irradia.composite(c, d)
    assert np.array_equal(view, snapshot)


def test_result_pool_is_bounded():
    from irradia import _irradia

    c, d = stack(2, dtype=np.float32)
    irradia.composite(c, d)
    allocated, _ = _irradia._pool_stats()
    for _ in range(50):  # freed at once: every call after the first reuses
        irradia.composite(c, d)
    assert _irradia._pool_stats()[0] == allocated
    # Beyond 64 MiB kept, the oldest freed buffer goes back to the system: two results
    # of 1700x1024 float RGBA + depth (2 x 34.8 MB) are freed, three buffers stay.
    big_c = np.zeros((1, 1024, 1700, 4), np.float32)
    big_d = np.zeros((1, 1024, 1700), np.float32)
    held = [irradia.composite(big_c, big_d) for _ in range(2)]
    allocated, reused = _irradia._pool_stats()
    del held
    held = [irradia.composite(big_c, big_d) for _ in range(2)]
    assert _irradia._pool_stats() == (allocated + 1, reused + 3)
