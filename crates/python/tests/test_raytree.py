"""Scene.trace_pixel: the ray tree as nested dicts, equal to `irradia trace-pixel --format json`."""

import json

import pytest

import irradia


@pytest.mark.parametrize(
    "name,x,y,extra",
    [("whitted", 640, 400, []), ("whitted", 10, 10, ["--max-depth", "2"]), ("cornell", 256, 300, [])],
)
def test_trace_pixel_equals_cli_json(cli, name, x, y, extra):
    r = cli("trace-pixel", "--builtin", name, x, y, "--format", "json", *extra)
    ref = json.loads(r.stdout)
    kw = {"max_depth": int(extra[1])} if extra else {}
    doc = irradia.builtin(name).trace_pixel(x, y, **kw)
    assert doc == ref


def test_tree_shape_and_radiance_matches_render():
    s = irradia.builtin("whitted")
    doc = s.trace_pixel(32, 20, width=64, height=48)
    tree = doc["tree"]
    assert tree["kind"] == "camera" and tree["depth"] == 1

    def count(n):
        return 1 + sum(count(c) for c in n["children"])

    assert count(tree) == doc["rays"]
    img = s.render(width=64, height=48)
    assert doc["radiance"] == pytest.approx(img[20, 32].tolist(), abs=0)


def test_trace_pixel_errors(cli):
    s = irradia.builtin("whitted")
    with pytest.raises(irradia.IrradiaError) as e:
        s.trace_pixel(5000, 1)
    r = cli("trace-pixel", "--builtin", "whitted", "5000", "1", check=False)
    assert r.returncode == 2 and str(e.value) in r.stderr
    with pytest.raises(OverflowError):
        s.trace_pixel(-1, 0)
