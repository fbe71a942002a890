"""Scene.render against the `irradia render` command, bit for bit; AOVs, progress,
threads, Ctrl-C and bad options."""

import os
import signal
import threading

import numpy as np
import pytest

import irradia


def read_pfm(path):
    """An independent PFM reader (bottom-to-top rows; negative scale: little endian)."""
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        dt = "<f4" if scale < 0 else ">f4"
        c = 3 if kind == b"PF" else 1
        a = np.frombuffer(f.read(), dtype=dt).reshape(h, w, c)
    return np.flipud(a).astype(np.float32)


@pytest.mark.parametrize(
    "name,args",
    [
        ("whitted", dict(width=64, height=48)),
        ("csg", dict(width=48, height=32, max_depth=3)),
        ("cornell", dict(width=32, height=32, spp=4)),
        ("whitted", dict(width=40, height=30, spp=3, integrator="path")),
    ],
)
def test_render_equals_cli_bit_for_bit(tmp_path, cli, name, args):
    out = tmp_path / "cli.pfm"
    flags = []
    for k, v in args.items():
        flags += ["--" + k.replace("_", "-"), str(v)]
    cli("render", "--builtin", name, *flags, "--threads", "2", "-o", out, "--quiet",
        "--aov", "depth,normal,object-id,ray-depth")
    r = irradia.builtin(name).render(threads=2, aovs=["depth", "normal", "object-id", "ray-depth"], **args)
    ref = read_pfm(out)
    assert r["color"].dtype == np.float32 and r["color"].shape == ref.shape
    assert np.array_equal(r["color"], ref)
    assert np.array_equal(r["color"], irradia.read_image(out))
    depth = read_pfm(tmp_path / "cli.depth.pfm")[..., 0]
    assert np.array_equal(r["depth"], depth)
    assert np.array_equal(r["normal"], read_pfm(tmp_path / "cli.normal.pfm"))
    ids = read_pfm(tmp_path / "cli.object-id.pfm")[..., 0]
    assert r["object-id"].dtype == np.int32 and np.array_equal(r["object-id"], ids.astype(np.int32))
    assert np.array_equal(r["ray-depth"], read_pfm(tmp_path / "cli.ray-depth.pfm")[..., 0].astype(np.int32))


def test_render_keeps_scene_settings():
    s = irradia.builtin("whitted")
    w, h = s.width, s.height
    s.render(width=16, height=8)
    assert (s.width, s.height) == (w, h)
    assert s.last_render["samples"] == 1 and s.last_render["rays"] > 0


def test_threads_do_not_change_the_image():
    s = irradia.builtin("cornell")
    a = s.render(width=24, height=24, spp=2, threads=1)
    b = s.render(width=24, height=24, spp=2, threads=2, tile_size=7)
    assert np.array_equal(a, b)


def test_aov_names():
    s = irradia.builtin("whitted")
    r = s.render(width=8, height=8, aovs="depth,object_id")
    assert set(r) == {"color", "depth", "object-id"}
    assert np.isinf(r["depth"]).any() or (r["object-id"] >= 0).all()
    with pytest.raises(irradia.IrradiaError, match="unknown AOV 'albedo'"):
        s.render(width=8, height=8, aovs=["albedo"])


def test_progress_callback():
    calls = []
    s = irradia.builtin("cornell")
    s.render(width=32, height=32, spp=8, threads=1, progress=lambda done, total: calls.append((done, total)))
    assert calls, "the callback was called"
    assert calls[-1] == (32 * 32 * 8, 32 * 32 * 8)
    dones = [d for d, _ in calls]
    assert dones == sorted(dones)


def test_progress_true_without_or_with_tqdm():
    s = irradia.builtin("whitted")
    img = s.render(width=16, height=16, progress=True)
    assert img.shape == (16, 16, 3)


def test_callback_exception_stops_the_render():
    class Stop(Exception):
        pass

    def cb(done, total):
        raise Stop("enough")

    s = irradia.builtin("cornell")
    with pytest.raises(Stop):
        s.render(width=256, height=256, spp=4096, threads=1, progress=cb)
    # The scene is intact afterwards.
    assert s.render(width=8, height=8, spp=1).shape == (8, 8, 3)


def test_ctrl_c_stops_a_render_cleanly():
    s = irradia.builtin("cornell")
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            s.render(width=512, height=512, spp=100000, threads=1)
    finally:
        timer.cancel()
    assert s.render(width=8, height=8, spp=1).shape == (8, 8, 3)


def test_bad_options_raise_cli_messages(tmp_path, cli):
    s = irradia.builtin("whitted")
    with pytest.raises(irradia.IrradiaError) as e:
        s.render(time=1.0)
    r = cli("render", "--builtin", "whitted", "--time", "1", "-o", tmp_path / "x.png", check=False)
    assert r.returncode == 2 and str(e.value) in r.stderr
    with pytest.raises(irradia.IrradiaError, match="--time: must be a positive"):
        irradia.builtin("cornell").render(time=-1.0)
    with pytest.raises(irradia.IrradiaError, match="unknown integrator"):
        s.render(integrator="bdpt")
    with pytest.raises(irradia.IrradiaError, match="image size"):
        s.render(width=0)
    with pytest.raises(irradia.IrradiaError, match="--resume"):
        irradia.builtin("cornell").render(resume=tmp_path / "none.ckpt")
    with pytest.raises(irradia.IrradiaError, match="progress"):
        s.render(width=4, height=4, progress=42)


def test_path_tracer_budget_and_checkpoint(tmp_path):
    s = irradia.builtin("cornell")
    ck = tmp_path / "c.ckpt"
    a = s.render(width=16, height=16, spp=4, checkpoint=ck)
    assert ck.is_file()
    b = s.render(width=16, height=16, spp=8, resume=ck)
    c = s.render(width=16, height=16, spp=8)
    assert np.array_equal(b, c)
    assert not np.array_equal(a, c)
