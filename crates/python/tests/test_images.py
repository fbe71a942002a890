"""read_image / write_image through Irradia's image files."""

import numpy as np
import pytest

import irradia


@pytest.mark.parametrize("ext", ["pfm", "exr"])
def test_float_round_trip_exact(tmp_path, ext):
    a = np.random.default_rng(0).uniform(0, 4, (7, 5, 3)).astype(np.float32)
    p = tmp_path / ("a." + ext)
    irradia.write_image(p, a)
    assert np.array_equal(irradia.read_image(p), a)


def test_png_is_srgb8(tmp_path):
    a = np.random.default_rng(0).uniform(0, 1, (6, 4, 3)).astype(np.float32)
    p = tmp_path / "a.png"
    irradia.write_image(p, a)
    b = irradia.read_image(p)
    assert b.shape == a.shape and np.abs(b - a).max() < 0.02
    u8 = np.random.default_rng(1).integers(0, 256, (3, 2, 3), dtype=np.uint8)
    irradia.write_image(p, u8)
    irradia.write_image(tmp_path / "b.png", irradia.read_image(p))
    assert (tmp_path / "b.png").read_bytes() == p.read_bytes()


def test_grey_and_float64(tmp_path):
    g = np.linspace(0, 1, 12, dtype=np.float64).reshape(3, 4)
    irradia.write_image(tmp_path / "g.pfm", g)
    r = irradia.read_image(tmp_path / "g.pfm")
    assert np.array_equal(r[..., 0], g.astype(np.float32)) and np.array_equal(r[..., 0], r[..., 2])


def test_image_errors(tmp_path):
    with pytest.raises(irradia.IrradiaError, match="unsupported image extension"):
        irradia.write_image(tmp_path / "a.tiff", np.zeros((2, 2, 3), np.float32))
    with pytest.raises(irradia.IrradiaError, match="shape"):
        irradia.write_image(tmp_path / "a.png", np.zeros((2, 2, 4), np.float32))
    with pytest.raises(OSError):
        irradia.write_image(tmp_path / "no" / "a.png", np.zeros((2, 2, 3), np.float32))
    with pytest.raises(FileNotFoundError):
        irradia.read_image(tmp_path / "none.png")
    (tmp_path / "x.pfm").write_bytes(b"garbage")
    with pytest.raises(OSError):
        irradia.read_image(tmp_path / "x.pfm")
